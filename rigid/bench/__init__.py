"""Speed measurements: the handout-style baseline, the MuJoCo peer, the engine, recording, grading.

May import every package but ``report`` and the CLI (the report reads the benchmark's JSON).
"""
