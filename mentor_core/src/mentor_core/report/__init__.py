"""The report wing: figures, tables and the Markdown report of runs and evaluations (paper
section IV).

May import every wing below it (errors, atomic, evolution, sim, objectives, files, training),
but never runtime or cli.
"""
