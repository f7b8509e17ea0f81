"""Drawing: the GGUI scene, the window and its panel, offscreen recording and video encoders.

May import the base modules, ``bodies``, ``engine`` and ``run``; never ``grading``, ``report``,
``science`` or ``bench``. The engine never imports this package.
"""
