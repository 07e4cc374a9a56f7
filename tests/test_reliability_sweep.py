"""Issue 24, class 3: sweeps that hung or crashed.  Every bound is checked before any work (one
line, exit 2, nothing written) and says the bound; a resumed sweep verifies every file it
reuses."""
from __future__ import annotations

import http.server
import os
import socket
import threading
import time

import pytest

from spectral_contact.cli.main import main
from spectral_contact.errors import InputError

pytest.importorskip("pandas")


def refused(argv, tmp_path, capsys, monkeypatch, words=()):
    monkeypatch.chdir(tmp_path)
    before = sorted(os.listdir(tmp_path))
    capsys.readouterr()
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0], err
    assert sorted(os.listdir(tmp_path)) == before
    for w in words:
        assert w in err[0], err[0]
    return err[0]


def test_the_product_of_the_option_lists_is_capped_before_it_is_enumerated(tmp_path, capsys,
                                                                           monkeypatch):
    from spectral_contact.sweep import MAX_SCENES

    t0 = time.perf_counter()
    refused(["sweep", "--load", "1:1000:1", "--mu", "1:1000:1", "--young", "1e6:1e7:1e6",
             "--out", "o", "--serial"], tmp_path, capsys, monkeypatch,
            ["1e+07 scenes", f"at most {MAX_SCENES}"])
    assert time.perf_counter() - t0 < 30  # not enumerated (10^7 dicts)


def test_workers_are_bounded_and_say_the_bound(tmp_path, capsys, monkeypatch):
    from spectral_contact.sweep import max_workers

    refused(["sweep", "--load", "100", "--out", "o", "--workers", "1000"], tmp_path, capsys,
            monkeypatch, [f"[1, {max_workers()}]", "per usable core"])


def test_empty_out_and_spec_among_the_outputs_are_refused(tmp_path, capsys, monkeypatch):
    refused(["sweep", "--load", "100", "--out", "", "--serial"], tmp_path, capsys, monkeypatch,
            ["--out"])
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "summary.csv").write_text("load = 100\n")
    refused(["sweep", "--spec", "o/summary.csv", "--out", "o", "--serial"], tmp_path, capsys,
            monkeypatch, ["--spec"])
    assert (tmp_path / "o" / "summary.csv").read_text() == "load = 100\n"


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *a):
        pass


@pytest.fixture
def http_server():
    srv = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _Quiet)
    t = threading.Thread(target=srv.serve_forever, daemon=True)
    t.start()
    yield f"tcp://127.0.0.1:{srv.server_address[1]}"
    srv.shutdown()


@pytest.fixture
def huge_frame_server():
    """Answers every connection with 64 bytes of 0xff: a dask frame length of ~1.8e19."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(8)
    stop = threading.Event()

    def serve():
        srv.settimeout(0.2)
        while not stop.is_set():
            try:
                c, _ = srv.accept()
            except OSError:
                continue
            c.sendall(b"\xff" * 64)
            c.close()

    t = threading.Thread(target=serve, daemon=True)
    t.start()
    yield f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    stop.set()
    t.join()
    srv.close()


def test_a_scheduler_that_is_an_http_server_fails_within_the_timeout(http_server, tmp_path, capsys,
                                                                     monkeypatch):
    pytest.importorskip("distributed")
    t0 = time.perf_counter()
    refused(["sweep", "--load", "100", "--out", "o", "--scheduler", http_server,
             "--scheduler-timeout", "1"], tmp_path, capsys, monkeypatch,
            ["no dask handshake within --scheduler-timeout 1 s"])
    assert time.perf_counter() - t0 < 20  # hung past any timeout before


def test_bytes_that_look_like_a_huge_frame_are_one_line(huge_frame_server, tmp_path, capsys,
                                                        monkeypatch):
    pytest.importorskip("distributed")
    refused(["sweep", "--load", "100", "--out", "o", "--scheduler", huge_frame_server,
             "--scheduler-timeout", "2"], tmp_path, capsys, monkeypatch, ["not a dask scheduler"])


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:", "tcp://127.0.0.1:99999", "tcp://:80"])
def test_a_scheduler_address_without_a_port_is_one_line(address, tmp_path, capsys, monkeypatch):
    pytest.importorskip("distributed")
    refused(["sweep", "--load", "100", "--out", "o", "--scheduler", address], tmp_path, capsys,
            monkeypatch, ["HOST:PORT"])


def test_a_resumed_sweep_recomputes_a_truncated_profile(tmp_path):
    from spectral_contact import sweep

    info = {}
    kw = dict(load="100,200", tol=1e-2, out=tmp_path / "o", engine="serial", profiles=True,
              progress=False)
    df = sweep(info=info, **kw)
    assert info["solved"] == 2
    files = sorted((tmp_path / "o" / "profiles").glob("*.csv"))
    whole = files[0].read_bytes()
    files[0].write_bytes(whole[: len(whole) // 2])  # truncated (a crash, a full disk, an editor)
    sweep(info=info, **kw)
    assert (info["reused"], info["solved"]) == (1, 1)
    assert files[0].read_bytes() == whole  # recomputed, the same bytes
    files[1].unlink()  # a missing one too
    df2 = sweep(info=info, **kw)
    assert (info["reused"], info["solved"]) == (1, 1)
    assert df2["key"].tolist() == df["key"].tolist()


def test_scene_product_helper_refuses_in_python():
    from spectral_contact.sweep import plan

    with pytest.raises(InputError, match="scenes: at most"):
        plan(load="1:1000:1", mu="1:1000:1")


def test_sweep_plot_and_profile_index(tmp_path, capsys, monkeypatch):
    """--plot: a column against one option, one curve per value of another (axes checked
    before any work); profiles/index.csv names the file of each scene."""
    import pandas as pd

    refused(["sweep", "--load", "100,200", "--out", "o", "--serial", "--plot", "p.png",
             "--plot-y", "nonsense"], tmp_path, capsys, monkeypatch, ["--plot-y nonsense"])
    refused(["sweep", "--load", "100,200", "--out", "o", "--serial", "--plot", "p.png",
             "--plot-x", "load", "--plot-group", "load"], tmp_path, capsys, monkeypatch,
            ["--plot-group"])
    assert main(["sweep", "--load", "100,200", "--mu", "0,1", "--tol", "1e-2", "--serial",
                 "--out", "o", "--profiles", "--plot", "p.png"]) == 0
    assert (tmp_path / "p.png").stat().st_size > 1000
    index = pd.read_csv(tmp_path / "o" / "profiles" / "index.csv")
    assert list(index.columns[:2]) == ["file", "maps_file"] and {"load_N_per_m", "mu"} <= set(index.columns)
    assert all((tmp_path / "o" / "profiles" / f).is_file() for f in index["file"])
    summary = pd.read_csv(tmp_path / "o" / "summary.csv")
    assert [f"{k}.csv" for k in summary["key"]] == index["file"].tolist()
