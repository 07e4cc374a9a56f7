"""Sweeps (issue 15): specs, the three engines giving one table, the store, failures, the CLI."""
import json
import os
import subprocess
import sys
import time

import numpy as np
import pytest

pd = pytest.importorskip("pandas", reason="the sweep extra is not installed")
pytest.importorskip("distributed", reason="the sweep extra is not installed")

from spectral_contact import solve  # noqa: E402
from spectral_contact import sweep as sweep_module  # noqa: E402
from spectral_contact.cli.main import main  # noqa: E402
from spectral_contact.errors import ConvergenceError, InputError  # noqa: E402
from spectral_contact.result import JSON_KEYS, JSON_KEYS_3D, MAP_KEYS, PROFILE_COLUMNS  # noqa: E402
from spectral_contact.sweep import TIMING_COLUMNS, parse_values, scene_key, sweep  # noqa: E402
from spectral_contact.sweep import engine as sweep_engine  # noqa: E402

# 12 scenes: 3 loads x 2 friction coefficients x 2 models
SPEC = {"load": "60:300:120", "mu": "0.5,2", "model": "exact,goodman", "tol": 1e-3}


def _untimed(df):
    return df.drop(columns=list(TIMING_COLUMNS))


def _same(a, b):
    """Identical tables: same columns, same values bit for bit (NaN == NaN), timings aside."""
    a, b = _untimed(a), _untimed(b)
    assert list(a.columns) == list(b.columns) and len(a) == len(b)
    for col in a.columns:
        x, y = a[col].tolist(), b[col].tolist()
        assert [repr(v) for v in x] == [repr(v) for v in y], col


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    out = tmp_path_factory.mktemp("serial")
    info = {}
    df = sweep(SPEC, out=out, engine="serial", progress=False, info=info, profiles=True)
    return df, out, info


def _same_profiles(a, b):
    """The profile files of two runs are the same, byte for byte (profiles/index.csv, the
    readable index beside them, is not a profile)."""
    def names(d):
        return sorted(p.name for p in (d / "profiles").glob("*.csv") if p.name != "index.csv")

    fa = names(a)
    assert fa == names(b) and len(fa) == 12
    for name in fa:
        assert (a / "profiles" / name).read_bytes() == (b / "profiles" / name).read_bytes(), name


# --- specifications -----------------------------------------------------------------------------
def test_parse_values_ranges_and_lists():
    assert parse_values("load", "20:380:40") == [20.0 + 40 * i for i in range(10)]
    assert parse_values("mu", "0.1:0.5:0.1") == [0.1, 0.2, 0.3, 0.4, 0.5]
    assert parse_values("mu", "0.3,1,2,3") == [0.3, 1.0, 2.0, 3.0]
    assert parse_values("mu", "0:1:0.5,3") == [0.0, 0.5, 1.0, 3.0]
    assert parse_values("grid_points", "1024,4096") == [1024, 4096]
    assert parse_values("model", ["exact", "goodman,exact"]) == ["exact", "goodman"]
    assert parse_values("load", 200) == [200.0]


@pytest.mark.parametrize("name, value, words", [
    ("load", "10:1:1", "empty range"), ("load", "0:10:-1", "step"), ("load", "0:10:0", "step"),
    ("mu", "1,,2", "empty value"), ("load", "1:2", "start:stop:step"), ("model", "foo", "--model"),
    ("bogus", "1", "unknown option 'bogus'"), ("grid_points", "2.5", "integer"), ("tol", "nan", "finite"),
])
def test_bad_specs_name_the_option(name, value, words):
    with pytest.raises(InputError, match=words):
        parse_values(name, value)


def test_key_depends_on_parameters_and_version():
    p = sweep_module.scenes({})[0]
    assert scene_key(p) == scene_key(dict(reversed(list(p.items()))))  # order does not matter
    assert scene_key(p) != scene_key(p | {"load": 201.0})
    assert scene_key(p) != scene_key(p, version="0.0.0")


def test_import_spectral_contact_does_not_import_pandas_or_distributed():
    code = ("import sys, spectral_contact; "
            "print('pandas' in sys.modules, 'distributed' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


# --- one table, three engines -------------------------------------------------------------------
def test_serial_table(serial):
    df, out, info = serial
    assert len(df) == 12 and set(df["status"]) == {"ok"} and info["solved"] == 12
    chosen = ("model", "method", "grid_points", "domain_length_m")
    given = {sweep_module.column(k) for k in sweep_module.OPTIONS}
    summary = [f"solved_{k}" if k in chosen else k for k in JSON_KEYS if k in chosen or k not in given]
    cols = list(df.columns)
    assert [cols.index(c) for c in summary] == sorted(cols.index(c) for c in summary)  # in order
    assert set(JSON_KEYS_3D) <= {c.removeprefix("solved_") for c in cols}
    # a row is the solve of its scene
    row = df.iloc[5]
    r = solve(load=row["load_N_per_m"], mu=row["mu"], model=row["model"], tol=row["tol"]).summary()
    for k in ("half_width_m", "contact_center_m", "indentation_m", "max_pressure_Pa"):
        assert row[k] == r[k]
    assert row["solved_model"] == row["model"] == "goodman" and row["mu"] == r["mu"]
    assert row["young_Pa"] == r["young_Pa"] and row["solved_grid_points"] == r["grid_points"]
    # the CSV: one header row, plain read_csv, the same numbers
    csv = pd.read_csv(out / "summary.csv")
    assert list(csv.columns) == list(df.columns) and len(csv) == 12
    back = pd.read_csv(out / "summary.csv")
    assert back["half_width_m"].tolist() == df["half_width_m"].tolist()
    assert len(list((out / "scenes").glob("*.json"))) == 12


def test_local_cluster_gives_the_same_table(serial, tmp_path):
    info = {}
    df = sweep(SPEC, out=tmp_path, workers=2, progress=False, info=info, profiles=True)
    assert info["engine"] == "LocalCluster(2 workers)" and info["solved"] == 12
    _same(df, serial[0])
    _same_profiles(tmp_path, serial[1])
    assert _untimed(pd.read_csv(tmp_path / "summary.csv")).equals(
        _untimed(pd.read_csv(serial[1] / "summary.csv")))


@pytest.fixture(scope="module")
def external_cluster(tmp_path_factory):
    """A dask scheduler and two workers on 127.0.0.1, stopped at the end."""
    d = tmp_path_factory.mktemp("cluster")
    sched_file = d / "scheduler.json"
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    procs = [subprocess.Popen(dask + ["--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                      "--scheduler-file", str(sched_file), "--idle-timeout", "300"],
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        t0 = time.time()
        while not sched_file.exists() and time.time() - t0 < 60:
            time.sleep(0.1)
        address = json.loads(sched_file.read_text())["address"]
        for _ in range(2):
            procs.append(subprocess.Popen(
                [sys.executable, "-m", "distributed.cli.dask_worker", address, "--nthreads", "1",
                 "--no-nanny", "--no-dashboard", "--host", "127.0.0.1", "--death-timeout", "60"],
                env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        from distributed import Client

        with Client(address, timeout=30) as c:
            c.wait_for_workers(2, timeout=60)
        yield address
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_external_cluster_gives_the_same_table(serial, external_cluster, tmp_path):
    info = {}
    df = sweep(SPEC, out=tmp_path, scheduler=external_cluster, progress=False, info=info,
               profiles=True)
    assert info["engine"] == f"scheduler {external_cluster}" and info["solved"] == 12
    _same(df, serial[0])
    _same_profiles(tmp_path, serial[1])


# --- the store ----------------------------------------------------------------------------------
def test_second_run_reuses_every_scene(serial, monkeypatch, capsys):
    df, out, _ = serial

    def no_solve(params):
        raise AssertionError("a stored scene was solved again")

    monkeypatch.setattr(sweep_engine, "_solve", no_solve)
    info = {}
    again = sweep(SPEC, out=out, engine="serial", info=info)
    assert info["reused"] == 12 and info["solved"] == 0
    assert "12 reused" in capsys.readouterr().err
    _same(again, df)
    assert again[list(TIMING_COLUMNS)].equals(df[list(TIMING_COLUMNS)])  # the stored rows


def test_interrupted_sweep_resumes(serial, tmp_path):
    done = []

    def stop_after_5(row):
        done.append(row["key"])
        if len(done) == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(SPEC, out=tmp_path, engine="serial", progress=False, on_row=stop_after_5)
    assert not (tmp_path / "summary.csv").exists()
    assert sorted(p.stem for p in (tmp_path / "scenes").glob("*.json")) == sorted(done)
    info = {}
    df = sweep(SPEC, out=tmp_path, engine="serial", progress=False, info=info)
    assert (info["reused"], info["solved"]) == (5, 7)
    _same(df, serial[0])
    # lost scene files (and a corrupt one) are solved again
    files = sorted((tmp_path / "scenes").glob("*.json"))
    files[0].unlink()
    files[1].unlink()
    files[2].write_text("{not json")
    df = sweep(SPEC, out=tmp_path, engine="serial", progress=False, info=info)
    assert (info["reused"], info["solved"]) == (9, 3)
    _same(df, serial[0])
    assert not list((tmp_path / "scenes").glob("*.tmp"))


def test_failing_scenes_are_rows(tmp_path, monkeypatch):
    real = sweep_engine._solve

    def flaky(params):
        if params["load"] < 0:
            return real(params)
        if params["mu"] == 1.0:
            raise ConvergenceError("contact iteration did not converge (residual 1e-2)")
        if params["mu"] == 3.0:
            raise RuntimeError("boom\nsecond line")
        return real(params)

    monkeypatch.setattr(sweep_engine, "_solve", flaky)
    info = {}
    df = sweep(load="-5,100", mu="0,1,3", tol=1e-3, out=tmp_path, engine="serial",
               progress=False, info=info)
    st = dict(zip(zip(df["load_N_per_m"], df["mu"]), df["status"]))
    assert st[(-5.0, 0.0)] == "input_error" and st[(100.0, 0.0)] == "ok"
    assert st[(100.0, 1.0)] == "not_converged" and st[(100.0, 3.0)] == "crashed"
    bad = df[df["load_N_per_m"] == -5.0].iloc[0]
    assert "load" in bad["message"] and np.isnan(bad["half_width_m"])
    assert df[df["mu"] == 3.0]["message"].iloc[1] == "RuntimeError: boom"
    assert info["statuses"] == {"ok": 1, "input_error": 3, "not_converged": 1, "crashed": 1}
    # crashed scenes are not stored: a rerun retries them (and only them)
    monkeypatch.setattr(sweep_engine, "_solve", real)
    df = sweep(load="-5,100", mu="0,1,3", tol=1e-3, out=tmp_path, engine="serial",
               progress=False, info=info)
    assert (info["reused"], info["solved"]) == (5, 1)
    assert df[df["load_N_per_m"] == 100.0]["status"].tolist() == ["ok", "not_converged", "ok"]
    csv = pd.read_csv(tmp_path / "summary.csv")
    assert csv["status"].tolist() == df["status"].tolist()


def test_profiles(tmp_path):
    df = sweep(load="100,200", mu=2.0, tol=1e-3, out=tmp_path, engine="serial",
               profiles=True, progress=False)
    key = df["key"].iloc[1]
    prof = pd.read_csv(tmp_path / "profiles" / f"{key}.csv")
    assert list(prof.columns) == list(PROFILE_COLUMNS)
    ref = solve(load=200.0, mu=2.0, tol=1e-3).profiles()
    for c in PROFILE_COLUMNS:
        assert np.array_equal(prof[c].to_numpy(), ref[c])


def test_parquet_when_pyarrow_is_installed(serial):
    pytest.importorskip("pyarrow")
    pq = pd.read_parquet(serial[1] / "summary.parquet")
    expected = serial[0].copy()
    expected["contact_intervals_m"] = [sweep_module._plain(v) for v in expected["contact_intervals_m"]]
    _same(pq, expected)


# --- the command line ---------------------------------------------------------------------------
def test_cli_sweep_with_spec_file(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text('load = "60:300:120"\nmu = [0.5, 2]\nmodel = ["exact"]\ntol = 1e-3\n')
    out = tmp_path / "res"
    assert main(["sweep", "--spec", str(spec), "--model", "exact,goodman", "--serial",
                 "--out", str(out), "--json"]) == 0
    cap = capsys.readouterr()
    rec = json.loads(cap.out)
    assert rec["scenes"] == 12 and rec["statuses"]["ok"] == 12 and cap.err == ""
    df = pd.read_csv(out / "summary.csv")
    assert sorted(set(df["model"])) == ["exact", "goodman"] and len(df) == 12
    assert main(["sweep", "--spec", str(spec), "--serial", "--out", str(out)]) == 0
    cap = capsys.readouterr()
    assert "6 reused, 0 solved" in cap.out and "6 reused" in cap.err


@pytest.mark.parametrize("argv", [
    ["--load", "10:1:1"], ["--load", "0:10:-5"], ["--mu", "0:1:0"], ["--bogus", "1"],
    ["--model", "foo"], ["--load", "abc"], ["--workers", "0"], ["--spec", "SPEC"],
    ["--spec", "missing.toml"], ["--scheduler", "tcp://127.0.0.1:9", "--scheduler-timeout", "1"],
])
def test_cli_bad_specs_exit_2_before_any_solve(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.toml").write_text("load = 200\nfriction = 2\n")
    argv = [a.replace("SPEC", "bad.toml") for a in argv]
    before = set(tmp_path.iterdir())

    def no_solve(params):
        raise AssertionError("solved before the spec was checked")

    monkeypatch.setattr(sweep_engine, "_solve", no_solve)
    assert main(["sweep", "--serial" if "--scheduler" not in argv and "--workers" not in argv
                 else "--json", *argv, "--out", "res"]) == 2
    assert set(tmp_path.iterdir()) == before  # nothing written
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err


# --- dask: a dead worker, Ctrl-C ----------------------------------------------------------------
def test_a_scene_that_kills_its_worker_is_a_crashed_row(tmp_path, monkeypatch):
    from distributed.diagnostics.plugin import WorkerPlugin

    from spectral_contact.sweep import local_client

    class KillOnOneScene(WorkerPlugin):  # defined here: shipped to the workers by value
        def setup(self, worker):
            import spectral_contact.sweep.engine as m

            real = m._solve

            def deadly(p):
                if p["mu"] == 2.0 and p["load"] == 180.0:
                    os._exit(1)
                return real(p)

            m._solve = deadly

    # on a loaded machine the nanny may stop restarting workers: the sweep must not hang
    monkeypatch.setattr(sweep_engine, "NO_WORKER_SECONDS", 10.0)
    client, cluster = local_client(2)
    try:
        client.register_plugin(KillOnOneScene())
        info = {}
        df = sweep(SPEC, client=client, out=tmp_path, progress=False, info=info)
    finally:
        client.close()
        cluster.close()
    culprits = (df["load_N_per_m"] == 180.0) & (df["mu"] == 2.0)
    assert len(df) == 12 and (df.loc[culprits, "status"] == "crashed").all()
    # dask counts a death against every task the worker held: a neighbour may be crashed too
    crashed = df[df["status"] == "crashed"]
    assert crashed["message"].str.match("KilledWorker|NoWorkersError").all()
    assert set(df["status"]) == {"ok", "crashed"}
    stored = {p.stem for p in (tmp_path / "scenes").glob("*.json")}
    assert stored == set(df.loc[df["status"] == "ok", "key"])  # crashed: not stored
    # a rerun (here serial, without the killer) solves exactly the crashed scenes
    df = sweep(SPEC, out=tmp_path, engine="serial", progress=False, info=info)
    assert (info["reused"], info["solved"]) == (12 - len(crashed), len(crashed))
    assert set(df["status"]) == {"ok"}


def test_interrupted_dask_sweep_keeps_finished_scenes(serial, tmp_path):
    done = []

    def stop_after_4(row):
        done.append(row["key"])
        if len(done) == 4:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        sweep(SPEC, out=tmp_path, workers=2, progress=False, on_row=stop_after_4)
    assert sorted(p.stem for p in (tmp_path / "scenes").glob("*.json")) == sorted(done)
    info = {}
    df = sweep(SPEC, out=tmp_path, engine="serial", progress=False, info=info)
    assert (info["reused"], info["solved"]) == (4, 8)
    _same(df, serial[0])


def test_map_tasks_keeps_order_and_raises(tmp_path):
    import math

    from spectral_contact.sweep import local_client, map_tasks

    items = [7, 3, 12, 0, 5]
    expected = [math.factorial(n) for n in items]
    assert map_tasks(math.factorial, items, engine="serial", progress=False) == expected
    client, cluster = local_client(2)
    try:
        assert map_tasks(math.factorial, items, client=client, progress=False) == expected
        with pytest.raises(ValueError):
            map_tasks(math.factorial, [1, -1, 2], client=client, progress=False)
    finally:
        client.close()
        cluster.close()


def test_batches_of_half_a_second_shrinking_to_a_twentieth_at_the_end():
    from spectral_contact.sweep import _batch_size

    ten_ms = [0.01] * 64
    assert _batch_size(ten_ms[:1], 400, 2) == 1          # until each thread has timed a scene
    assert _batch_size(ten_ms, 400, 2) == 50             # 0.5 s of 10 ms scenes
    assert _batch_size([0.001] * 8, 4000, 2) == 64       # at most MAX_BATCH
    assert _batch_size(ten_ms, 60, 2) == 15              # the end of the queue: a quarter per thread
    assert _batch_size(ten_ms, 8, 2) == 5                # ... but 0.05 s at least
    assert _batch_size([2.0] * 8, 400, 2) == 1           # scenes of seconds one by one


def _worker_settings():
    import dask

    return (dask.config.get("distributed.worker.profile.enabled"),
            dask.config.get("distributed.worker.memory.monitor-interval"),
            os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OPENBLAS_NUM_THREADS"))


def test_local_cluster_settings_reach_the_workers_and_stay_there(monkeypatch):
    import dask

    from spectral_contact.sweep import DASK_CONFIG, local_client

    # a dask Nanny started earlier in this process (default config) leaves the variable in
    # os.environ, which the workers would inherit: this test is about the sweep's own settings
    monkeypatch.delenv("MALLOC_TRIM_THRESHOLD_", raising=False)
    before = {k: dask.config.get(k, default="absent") for k in DASK_CONFIG}
    client, cluster = local_client(1)
    try:
        settings = list(client.run(_worker_settings).values())
    finally:
        client.close()
        cluster.close()
    assert settings == [(False, DASK_CONFIG["distributed.worker.memory.monitor-interval"], None, "1")]
    # this process's config is as it was (set only around the cluster's creation)
    assert {k: dask.config.get(k, default="absent") for k in DASK_CONFIG} == before
    assert before["distributed.worker.profile.enabled"] is not False  # dask's default: a real change
    assert "MALLOC_TRIM_THRESHOLD_" not in os.environ


def test_missing_extra_is_one_line_naming_it(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if dask.distributed were absent
    assert main(["sweep", "--load", "100", "--tol", "1e-3", "--workers", "2",
                 "--out", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err
    assert "spectral_contact[sweep]" in err and "--serial" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "a").exists()
    assert main(["sweep", "--load", "100", "--tol", "1e-3", "--serial", "--json",
                 "--out", str(tmp_path / "b")]) == 0  # serial needs pandas only
    monkeypatch.setitem(sys.modules, "pandas", None)
    assert main(["sweep", "--load", "100", "--serial", "--out", str(tmp_path / "c")]) == 2
    assert "spectral_contact[sweep]" in capsys.readouterr().err
    assert not (tmp_path / "c").exists()


def test_a_scheduler_without_workers_is_a_bad_spec(tmp_path):
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=0, processes=False, dashboard_address=None,
                      scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"}) as cluster, \
            Client(cluster, set_as_default=False) as client:
        with pytest.raises(InputError, match="no workers"):
            sweep(SPEC, client=client, out=tmp_path / "res", progress=False, scheduler_timeout=0.5)
    assert not (tmp_path / "res").exists()


def test_a_cluster_that_loses_its_workers_does_not_hang(tmp_path, monkeypatch):
    from distributed import Client, LocalCluster

    monkeypatch.setattr(sweep_engine, "NO_WORKER_SECONDS", 1.0)
    with LocalCluster(n_workers=1, processes=False, threads_per_worker=1, dashboard_address=None,
                      scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"}) as cluster, \
            Client(cluster, set_as_default=False) as client:
        seen = []

        def lose_workers_after_2(row):
            seen.append(row)
            if len(seen) == 2:
                cluster.scale(0)

        info = {}
        df = sweep(SPEC, client=client, out=tmp_path, progress=False, on_row=lose_workers_after_2,
                   info=info)
    assert len(df) == 12 and info["statuses"]["ok"] >= 2
    left = df[df["status"] == "crashed"]
    assert len(left) == 12 - info["statuses"]["ok"] > 0
    assert left["message"].str.startswith("NoWorkersError: the cluster has had no worker").all()
    assert len(list((tmp_path / "scenes").glob("*.json"))) == info["statuses"]["ok"]



# --- 3D -----------------------------------------------------------------------------------------
SPEC3D = {"indenter": "sphere", "force": "0.5,1", "mu": "0,1", "tol": 1e-2}


def test_3d_sweep_serial_and_local_cluster_agree(tmp_path):
    a = sweep(SPEC3D, out=tmp_path / "s", engine="serial", progress=False, profiles=True)
    b = sweep(SPEC3D, out=tmp_path / "l", workers=2, progress=False, profiles=True)
    assert len(a) == 4 and set(a["status"]) == {"ok"} and set(a["indenter"]) == {"sphere"}
    _same(a, b)
    assert a["load_N_per_m"].isna().all() and a["contact_radius_m"].gt(0).all()
    r = solve(indenter="sphere", force=1.0, mu=1.0, tol=1e-2).summary()
    row = a[(a["force_N"] == 1.0) & (a["mu"] == 1.0)].iloc[0]
    for k in ("contact_radius_m", "indentation_m", "max_pressure_Pa", "pressure_centroid_x_m"):
        assert row[k] == r[k]
    assert [row["solved_grid_points"], row["solved_grid_points_y"]] == r["grid_points"]
    for key in a["key"]:
        for d in ("s", "l"):
            assert (tmp_path / d / "profiles" / f"{key}.csv").is_file()
        ms, ml = (np.load(tmp_path / d / "profiles" / f"{key}.npz") for d in ("s", "l"))
        assert sorted(ms.files) == sorted(MAP_KEYS)
        for k in MAP_KEYS:
            assert np.array_equal(ms[k], ml[k])


def test_line_and_3d_in_one_table(tmp_path):
    df = sweep(indenter="line,sphere", mu="0,1", tol=1e-2, out=tmp_path, engine="serial",
               progress=False)
    line, sphere = df[df["indenter"] == "line"], df[df["indenter"] == "sphere"]
    assert len(line) == len(sphere) == 2 and set(df["status"]) == {"ok"}
    assert (line["load_N_per_m"] == 200.0).all() and line["force_N"].isna().all()  # per indenter
    assert (sphere["force_N"] == 1.0).all() and sphere["load_N_per_m"].isna().all()
    assert line["contact_radius_m"].isna().all() and sphere["half_width_m"].isna().all()
    assert len(pd.read_csv(tmp_path / "summary.csv")) == 4
    # a parameter of the other kind is a row with its status, not the end of the sweep
    bad = sweep(indenter="line,sphere", force=1.0, tol=1e-2, engine="serial", progress=False)
    assert bad["status"].tolist() == ["input_error", "ok"] and "force" in bad["message"].iloc[0]


def test_summary_csv_opens_with_numpy_too(tmp_path):
    df = sweep(indenter="line,sphere", load=None, mu="0,1", tol=1e-2, model="exact,auto",
               out=tmp_path, engine="serial", progress=False)
    text = (tmp_path / "summary.csv").read_text()
    assert '"' not in text  # nothing quoted: every reader splits the columns the same way
    arr = np.genfromtxt(tmp_path / "summary.csv", delimiter=",", names=True, dtype=str,
                        encoding="utf-8")
    assert len(arr) == len(df) == 8 and len(arr.dtype.names) == len(df.columns)
    back = pd.read_csv(tmp_path / "summary.csv")
    assert back["half_width_m"].tolist()[:4] == df["half_width_m"].tolist()[:4]
    for c in ("solved_grid_points", "solved_grid_points_y", "solved_domain_length_y_m"):
        assert back[c].equals(df[c].astype(float)), c  # numbers, lines and surfaces alike
    iv = back.loc[back["indenter"] == "line", "contact_intervals_m"].iloc[0]
    assert json.loads(iv.replace(";", ",")) == df.loc[df["indenter"] == "line", "contact_intervals_m"].iloc[0]
