#!/usr/bin/env python3
"""``hfi run`` under its old name (hfi/cli.py): scripts/run.py [FILE] [--backend B] [--out DIR] [--quiet] [--fst F]."""
import sys
from hfi.cli import main
sys.exit(main(["run", *sys.argv[1:]]))
