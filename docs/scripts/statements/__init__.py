"""The thesis' statements of chapters 3 and 4.1 read literally on a sweep's Parquet tables.

`sweep` loads the tables, `readings` holds the tests a statement is read as (trends in e,
extrema at the centre, moments against the Gaussian, ...), `chapter3` and `chapter41` list the
statements, one function each. `docs/scripts/thesis_statements.py` prints them.
"""
