"""Issue 24, classes 1-2: no output over an input or another output (implicit metadata
included, hard links included), and one commit for all of a command's outputs, stdout included.

Every refused command: exit 2, one stderr line naming the options as typed, the inputs
unchanged, nothing new in the folder.
"""
from __future__ import annotations

import errno
import hashlib
import io
import os
import sys
from pathlib import Path

import pytest

from spectral_contact.cli.main import main

from .test_reliability import _profile_csv, _radial_csv

FAST = ["--tol", "1e-3"]


def _snapshot(d):
    return {n: (os.path.islink(d / n), hashlib.sha256((d / n).read_bytes()).hexdigest()
                if (d / n).is_file() else None) for n in os.listdir(d)}


def refused(argv, tmp_path, capsys, monkeypatch, words=()):
    monkeypatch.chdir(tmp_path)
    before = _snapshot(tmp_path)
    capsys.readouterr()
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert _snapshot(tmp_path) == before  # inputs untouched, nothing new, no temporary
    for w in words:
        assert w in err[0], err[0]
    return err[0]


@pytest.fixture
def files(tmp_path):
    _profile_csv(tmp_path / "M.csv")
    _radial_csv(tmp_path / "U.csv")
    (tmp_path / "G.csv").write_text("r_m,G_per_m2\n0,1e6\n1e-4,9e5\n2e-4,5e5\n3e-4,1e5\n4e-4,0\n")
    return tmp_path


@pytest.mark.parametrize("argv, words", [
    (["solve", "--sensor", "--apparatus-zz", "G.csv", "--profiles", "G.csv"],
     ["--profiles G.csv", "input --apparatus-zz G.csv"]),
    (["solve", "--sensor", "--apparatus-xz", "G.csv", "--plot", "G.csv"], ["--apparatus-xz"]),
    (["calibrate", "--measured", "U.csv", "--punch-load", "1", "--out", "U.csv"],
     ["--out U.csv", "--measured U.csv"]),
    (["calibrate", "--measured", "U.csv", "--punch-load", "1", "--plot", "U.csv"], ["--measured"]),
    (["calibrate", "--measured", "U.csv", "--punch-load", "1", "--out", "U"], []),  # U.meta.json
    (["compare", "M.csv", "--plot", "M.csv"], ["--plot M.csv", "MEASURED.csv M.csv"]),
    (["compare", "M.csv", "--apparatus-zz", "G.csv", "--plot", "./G.csv"], ["--apparatus-zz"]),
    (["solve", "--indenter", "sphere", "--profiles", "p.csv", "--maps", "p.meta.json"],
     ["metadata p.meta.json", "--maps p.meta.json"]),
    (["solve", "--profiles", "p.csv", "--plot", "p.meta.json"], []),
])
def test_an_output_never_names_an_input_or_another_output(argv, words, files, capsys, monkeypatch):
    if argv[-1] == "U":  # the implicit metadata of --out U is U.meta.json: here an input
        os.rename(files / "U.csv", files / "U.meta.json")
        argv = [a.replace("U.csv", "U.meta.json") for a in argv]
    refused(argv, files, capsys, monkeypatch, words)


def test_a_hard_link_to_an_input_is_the_input(files, capsys, monkeypatch):
    os.link(files / "G.csv", files / "link.csv")
    refused(["solve", "--sensor", "--apparatus-zz", "link.csv", "--profiles", "G.csv"], files,
            capsys, monkeypatch, ["would overwrite the input --apparatus-zz link.csv"])
    os.symlink("G.csv", files / "sym.csv")
    refused(["solve", "--sensor", "--apparatus-zz", "sym.csv", "--profiles", "G.csv"], files,
            capsys, monkeypatch, ["would overwrite"])


def test_metadata_that_is_a_directory_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    (tmp_path / "p.meta.json").mkdir()
    err = refused(["solve", *FAST, "--profiles", "p.csv", "--plot", "p.png"], tmp_path, capsys,
                  monkeypatch)
    assert "p.meta.json" in err and ".tmp" not in err


class _Full(io.StringIO):
    """A stdout that refuses every byte, as > /dev/full does."""

    def write(self, s):
        raise OSError(errno.ENOSPC, "No space left on device")

    def flush(self):
        raise OSError(errno.ENOSPC, "No space left on device")


@pytest.mark.parametrize("argv", [
    ["solve", *FAST, "--json", "--profiles", "p.csv", "--plot", "p.png"],
    ["calibrate", "--measured", "U.csv", "--punch-load", "0.01", "--n-boot", "0", "--out", "g.csv"],
])
def test_full_stdout_writes_no_file(argv, files, capsys, monkeypatch):
    monkeypatch.chdir(files)
    before = _snapshot(files)
    monkeypatch.setattr(sys, "stdout", _Full())
    monkeypatch.setattr("spectral_contact.cli.files._silence_stdout", lambda: None)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["error: standard output: No space left on device"]
    assert _snapshot(files) == before


def test_closed_stdout_is_refused_before_any_work(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(sys, "stdout", None)
    err = refused(["solve", "--profiles", "p.csv"], tmp_path, capsys, monkeypatch)
    assert "standard output is closed" in err


def test_closed_and_full_stdout_in_a_real_process(tmp_path):
    import subprocess

    root = str(Path(__file__).resolve().parent.parent)  # this checkout's package
    env = dict(os.environ, PYTHONPATH=root + os.pathsep + os.environ.get("PYTHONPATH", ""))
    argv = [sys.executable, "-m", "spectral_contact.cli.main", "solve", *FAST, "--json",
            "--profiles", "p.csv"]
    p = subprocess.run(argv, cwd=tmp_path, capture_output=False, stderr=subprocess.PIPE,
                       text=True, env=env, stdout=open("/dev/full", "w"), timeout=120)
    assert (p.returncode, p.stderr.strip().splitlines()) == (
        2, ["error: standard output: No space left on device"])
    p = subprocess.run(argv, cwd=tmp_path, stderr=subprocess.PIPE, text=True, env=env,
                       preexec_fn=lambda: os.close(1), timeout=120)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert os.listdir(tmp_path) == []


def test_a_write_error_names_the_users_file_and_nothing_remains(tmp_path, capsys, monkeypatch):
    """ENOSPC while a file is staged (no file name in the error, as the kernel gives it): the
    message names the user's path, never the temporary; the other staged file is removed."""
    import spectral_contact.cli.main as cli

    def full(path, *a, **k):
        with open(path, "w") as fh:
            fh.write("x")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(cli, "write_csv", full, raising=False)
    monkeypatch.setattr("spectral_contact.cli.files.write_csv", full)
    err = refused(["solve", *FAST, "--profiles", "p.csv"], tmp_path, capsys, monkeypatch)
    assert err == "error: p.csv: No space left on device"


def test_a_failed_rename_restores_the_files_already_replaced(tmp_path):
    """The commit's renames are undone when one fails: the old contents come back."""
    from spectral_contact.cli.files import Outputs

    (tmp_path / "a.csv").write_text("old a")
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "x").write_text("in the way")
    with pytest.raises(OSError) as info:
        with Outputs() as outs:
            outs.path(tmp_path / "a.csv").write_text("new a")
            outs.path(tmp_path / "b").write_text("new b")  # b is a non-empty folder: fails
    assert info.value.filename == str(tmp_path / "b")
    assert (tmp_path / "a.csv").read_text() == "old a"
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "b"]


def test_invert_uses_the_shared_check(files, capsys, monkeypatch):
    """invert (issue 21's command): its --out's implicit metadata may not be its record, nor a
    hard link to it."""
    os.rename(files / "M.csv", files / "M.meta.json")
    refused(["invert", "M.meta.json", "--out", "M"], files, capsys, monkeypatch,
            ["metadata", "would overwrite the input FILE M.meta.json"])
    os.link(files / "M.meta.json", files / "hl.csv")
    refused(["invert", "hl.csv", "--plot", "x.png", "--out", "M.meta.json"], files, capsys,
            monkeypatch, ["would overwrite the input FILE hl.csv"])
