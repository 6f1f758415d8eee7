"""Everything FMI: the variable table, model descriptions, the FMU builders and the
FMU-instance wrapper a co-simulation master uses (docs/reference/fmu.md, "The FMU").

Importing this package loads nothing heavy; fmpy and pythonfmu are imported by
the functions that need them.
"""
