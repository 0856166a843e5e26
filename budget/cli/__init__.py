"""The ``sar-budget`` command line: a thin layer over the library."""
