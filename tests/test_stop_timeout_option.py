"""``armplan stop --timeout`` that is no wait: refused before connecting.

The same check and words as ``plan``'s and ``fit``'s ``--timeout``
(``armplan.cli.remote.check_timeout``): stop named the field ``--timeout``
in its JSON error where they name it ``timeout``.
"""

from __future__ import annotations

import json

import pytest

from armplan.cli.main import main
from armplan.launch import free_endpoint


@pytest.mark.parametrize("wait", ["nan", "-1", "0", "1e9"])
def test_a_timeout_that_is_no_wait_is_refused_naming_the_field_as_plan_does(
    wait: str, capsys: pytest.CaptureFixture[str]
) -> None:
    where = ["--connect", free_endpoint()]  # nothing listens: never reached
    code = main(["stop", *where, "--timeout", wait, "--json"])
    out = capsys.readouterr().out
    assert code == 1
    error = json.loads(out)["error"]
    assert error["kind"] == "invalid_input"
    assert error["evidence"] == {"field": "timeout"}
    assert error["message"].startswith(
        "--timeout must be a positive number of seconds up to 86400, got "
    )
