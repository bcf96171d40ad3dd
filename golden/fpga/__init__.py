"""Bit-true models of the FPGA data path (docs/spec.md, sections 2-3)."""
