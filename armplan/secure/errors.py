"""The error of setting up a secured Zenoh (certificates, passwords, files)."""

from __future__ import annotations

from typing import Any

from shared.errors import ArmplanError


class SecureSetupError(ArmplanError):
    """Certificates, passwords or configuration files could not be written.

    Attributes:
        path: The file or folder concerned (may be empty).
    """

    kind = "secure_setup"

    def __init__(self, message: str, *, path: str = "", **evidence: Any) -> None:
        super().__init__(message, path=path, **evidence)
        self.path = path
