"""``python -m armplan`` runs the command line."""

from armplan.cli.main import main

raise SystemExit(main())
