"""One module per ``armplan`` subcommand.

Each module defines ``add_parser(commands)`` (register the subcommand and set
``run``) and ``run(args) -> int``. Modules here are found automatically; an
optional ``ORDER`` integer sorts them in ``armplan --help`` (default 100).
"""
