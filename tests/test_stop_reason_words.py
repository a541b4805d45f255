"""``armplan stop --reason``'s warnings count in good English.

``--reason $'e-stop\\nbutton'`` said "1 control characters in the reason
were removed".
"""

from __future__ import annotations

import subprocess
import sys

from armplan.launch import free_endpoint
from shared.messages.stop import clean_reason


def test_one_removed_character_is_singular() -> None:
    """A real ``armplan stop`` (no router: it warns before it connects)."""
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "armplan",
            "stop",
            "--connect",
            free_endpoint(),
            "--reason",
            "e-stop\nbutton",
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1  # no router there
    assert done.stderr.startswith(
        "armplan: warning: 1 control character in the reason was removed\n"
    )
    reason, problems = clean_reason("e-stop\r\nbutton")  # two: plural, as before
    assert reason == "e-stop  button"
    assert problems == ["2 control characters in the reason were removed"]
