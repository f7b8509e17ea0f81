"""Drawing: a software renderer for the scene (with contact shadows), the camera (framing, --camera,
follow), the GGUI window, its panel and mouse grab, recording, notebook videos (rigid.show) and
video encoders. The renderer's kernels take ndarrays (raster.py, raster_emit.py, shadow.py): they
compile once per process, not once per renderer.

May import the base modules, ``bodies``, ``engine`` and ``run``; never ``grading``, ``report``,
``science`` or ``bench``. The engine never imports this package.
"""
