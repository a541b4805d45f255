"""The ``armplan`` command line: one module per command."""
