"""Drawing: a software renderer for the scene, the GGUI window and its panel, recording and video encoders.

May import the base modules, ``bodies``, ``engine`` and ``run``; never ``grading``, ``report``,
``science`` or ``bench``. The engine never imports this package.
"""
