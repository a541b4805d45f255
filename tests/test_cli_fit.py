"""armplan demos synth / info and armplan fit: progress, rate table, held-out report."""

from __future__ import annotations

import json
import os
import pathlib
import stat
import threading

import pytest

from armplan.cli.main import main
from services.fit import load_model


@pytest.fixture(scope="module")
def demos(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    path = tmp_path_factory.mktemp("demos") / "demos.mcap"
    assert (
        main(["demos", "synth", "-o", str(path), "--subjects", "4", "--trials", "1"])
        == 0
    )
    return path


def test_synth_and_info(
    demos: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """info counts the synthetic file's subjects, trials and labels."""
    capsys.readouterr()
    assert main(["demos", "info", str(demos), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["subjects"] == ["S01", "S02", "S03", "S04"]
    assert info["trials"] == 64
    assert info["labels"]["S_R E_P W_P"] > 0


def test_fit_prints_rates_and_cross_validation(
    demos: pathlib.Path, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """fit writes the model and prints each rate with its LOO CV log-likelihood."""
    out = tmp_path / "model.json"
    assert main(["fit", str(demos), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    model = load_model(out)
    assert "LOO CV log-lik." in text
    for variable in model.variables:
        assert variable.name in text and f"{variable.rate:.4f}" in text


def test_fit_hold_out_reports_agreement_and_confusion(
    demos: pathlib.Path, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--hold-out 1 fits on three subjects and compares with the fourth."""
    out = tmp_path / "model.json"
    assert main(["fit", str(demos), "-o", str(out), "--hold-out", "1", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["held_out"]["subjects"] == ["S04"]
    assert report["subjects"] == ["S01", "S02", "S03"]
    confusion = report["held_out"]["confusion"]
    total = sum(sum(row) for row in confusion.values())
    assert total == report["held_out"]["samples"]
    assert 0.0 <= report["held_out"]["agreement"] <= 1.0


def test_fit_refuses_a_bad_hold_out(
    demos: pathlib.Path, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Holding out every subject is an error naming the option."""
    assert (
        main(["fit", str(demos), "-o", str(tmp_path / "m.json"), "--hold-out", "4"])
        == 1
    )
    assert "--hold-out must be 0..3" in capsys.readouterr().err


def test_fit_of_a_truncated_file_is_a_clear_error(
    demos: pathlib.Path, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A truncated demonstration file stops the fit with the file named."""
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(demos.read_bytes()[:20000])
    assert main(["fit", str(cut), "-o", str(tmp_path / "m.json")]) == 1
    assert f"{cut}: truncated" in capsys.readouterr().err


@pytest.mark.parametrize(
    "option,value,words",
    [
        ("--bins", "1", "bins must be 2..64, got 1"),
        ("--smoothing", "nan", "smoothing must be in (0, 1e+06], got nan"),
    ],
)
def test_fit_options_out_of_range_are_refused_before_reading(
    demos: pathlib.Path,
    tmp_path: pathlib.Path,
    capsys: pytest.CaptureFixture[str],
    option: str,
    value: str,
    words: str,
) -> None:
    """An option out of range was refused only once every file was read (10 s
    for the full synthetic set): a damaged file shows it comes first now."""
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(demos.read_bytes()[:20000])
    out = tmp_path / "m.json"
    assert main(["fit", str(cut), "-o", str(out), option, value]) == 1
    err = capsys.readouterr().err
    assert words in err and "truncated" not in err
    assert not out.exists()


def test_fit_writes_into_a_fifo_not_over_it(
    demos: pathlib.Path, tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o naming no regular file is written into. The model was renamed over
    it: run as root, ``-o /dev/full`` put a regular file in the device's
    place and said "written to /dev/full" (a FIFO stands in for the device)."""
    fifo = tmp_path / "model.pipe"
    os.mkfifo(fifo)
    got: list[str] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()), daemon=True)
    reader.start()
    assert main(["fit", str(demos), "-o", str(fifo), "--json"]) == 0
    reader.join(timeout=60)
    assert stat.S_ISFIFO(fifo.stat().st_mode)
    assert len(got) == 1 and json.loads(got[0])["version"] == 1
    assert json.loads(capsys.readouterr().out)["model"] == str(fifo)


def test_fit_through_a_link_replaces_its_target(
    demos: pathlib.Path, tmp_path: pathlib.Path
) -> None:
    """-o latest.json, a link to a dated model: the link was replaced by a
    regular file, the dated model left stale; now the link stays and its
    target holds the new model, keeping its mode."""
    dated = tmp_path / "model-2026-11.json"
    dated.write_text("{}")
    dated.chmod(0o640)
    link = tmp_path / "latest.json"
    link.symlink_to(dated.name)
    assert main(["fit", str(demos), "-o", str(link), "--json"]) == 0
    assert link.is_symlink()
    assert load_model(dated).samples > 0
    assert stat.S_IMODE(dated.stat().st_mode) == 0o640


def test_fit_of_a_c3d_capture_says_to_import_it_first(
    tmp_path: pathlib.Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A C3D capture given to fit was "not an MCAP file", no more: the README
    lists C3D beside `armplan fit`, and the lab did not learn the step it
    missed. Now the error names `armplan demos import`; nothing is written."""
    from tests.test_demos_c3d import write_reach_c3d

    capture = tmp_path / "reach.c3d"
    write_reach_c3d(capture)
    out = tmp_path / "m.json"
    assert main(["fit", str(capture), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"{capture}: not an MCAP file" in err
    assert "is imported first, 'armplan demos import FILE --markers" in err
    assert not out.exists()
