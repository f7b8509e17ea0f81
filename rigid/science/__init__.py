"""Physics judged from outside: closed-form and scipy references, experiments, the validation table.

May import the base modules, ``bodies``, ``engine`` and ``run``.
"""
