#!/usr/bin/env python3
"""``hfi paper`` under its old name (hfi/cli.py, hfi/reproduce.py): [--short] [--only G,...] [--jobs N] [--out DIR]."""
import sys
from hfi.cli import main
sys.exit(main(["paper", *sys.argv[1:]]))
