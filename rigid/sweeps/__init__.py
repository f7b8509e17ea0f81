"""Many runs of one scene: ``python -m rigid sweep`` and ``rigid.sweep`` (docs/sweeps.md).

- vary.py     ``--vary KEY=START:STOP:N`` / ``KEY=a,b,c``: the values, checked; the runs, their product
- task.py     one run in a worker process: Taichi started once, the run's NPZ (and MP4) as bytes
- batch.py    runs that differ only in their bodies' starts, as the worlds of one Simulator
- pool.py     the local process pool (a worker that dies fails only the run it held)
- cluster.py  the same tasks on a Ray cluster (``--ray ADDRESS|local``; the ``cluster`` extra)
- folder.py   the output folder: index.csv, runs/<run>.npz, sweep.json; resume; atomic writes
- driver.py   plan, check, resume, dispatch, write: the one function the CLI and the API call
- command.py  the ``sweep`` subcommand's arguments

Workers compute and return bytes; only the driver writes into the output folder, each file
atomically, so a Ctrl-C or a killed worker leaves complete files only. May import the base
modules, ``bodies``, ``engine``, ``run`` and ``view`` (recording); never the CLI. (Not named
``sweep``: importing it would put the module where ``rigid.sweep``, the API's function, is.)
"""
