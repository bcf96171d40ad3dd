"""Shared input vectors of the block tests: the cocotb testbenches (RTL) and the HLS C-simulation tests."""
