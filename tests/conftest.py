"""Shared pytest fixtures of tests/."""

from __future__ import annotations

import os
import secrets

import pytest


@pytest.fixture(scope="module")
def seed() -> int:
    """Seed of a test module's random vectors: ``HFI_SEED`` if set (decimal or 0x...), else a fresh
    one; printed, so a failure replays with ``HFI_SEED=<seed> make test``."""
    env = os.environ.get("HFI_SEED")
    value = int(env, 0) if env else secrets.randbits(32)
    print(f"HFI_SEED={value}")
    return value
