"""``python -m debench`` runs the command-line interface."""

from debench.reference.cli import main

raise SystemExit(main())
