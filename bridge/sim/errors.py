"""The error the simulated NAO raises when it refuses a command."""

from __future__ import annotations


class SimCommandError(ValueError):
    """A command the simulated NAO refuses, nothing of it executed.

    Raised inside a served ALMotion method, it reaches the caller as libqi's
    ``RuntimeError`` whose text starts with ``SimCommandError: <reason>``.
    """
