"""A batch on a Dask distributed cluster gives the same rows as a local run.

The cluster is a LocalCluster on loopback (TCP on 127.0.0.1), with its workers
as threads of this process so that the test stays fast; the client side is
exactly what runs against a real cluster.
"""

from __future__ import annotations

import json

import pytest
import trimesh

from dentopo import compute_batch
from dentopo.cli import main
from dentopo.cli._arguments import SCHEDULER_ENV
from dentopo.samples import tooth

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=2,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        yield cluster


@pytest.fixture
def folder(tmp_path):
    for i in range(3):
        tooth(rings=8 + 2 * i).export(tmp_path / f"tooth{i}.ply")
    trimesh.creation.icosphere(subdivisions=2).export(tmp_path / "sphere.obj")
    (tmp_path / "broken.ply").write_bytes(b"ply\nformat ascii 1.0\n")
    return tmp_path


def without_seconds(records):
    return [{k: v for k, v in r.items() if k != "seconds"} for r in records]


def test_cluster_rows_equal_local_rows(cluster, folder):
    local = compute_batch(folder)
    remote = compute_batch(folder, scheduler=cluster.scheduler_address)
    assert without_seconds(remote) == without_seconds(local)
    assert [r["status"] for r in remote].count("error") == 1


def test_cli_scheduler_option_and_environment_variable(cluster, folder, tmp_path, monkeypatch):
    local = tmp_path / "local.json"
    assert main([str(folder), "-o", str(local), "-q"]) == 1
    by_option = tmp_path / "option.json"
    address = cluster.scheduler_address
    assert main([str(folder), "--scheduler", address, "-o", str(by_option), "-q"]) == 1
    monkeypatch.setenv(SCHEDULER_ENV, address)
    by_env = tmp_path / "env.csv.json"
    assert main([str(folder), "-o", str(by_env), "-q", "--per-vertex", str(tmp_path / "pv")]) == 1
    expected = without_seconds(json.loads(local.read_text()))
    assert without_seconds(json.loads(by_option.read_text())) == expected
    assert without_seconds(json.loads(by_env.read_text())) == expected
    assert len(list((tmp_path / "pv").glob("*.dentopo.ply"))) == 4  # written by the workers


def test_unreachable_scheduler_is_a_usage_error(folder, capsys):
    import dask

    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}):
        assert main([str(folder), "--scheduler", "tcp://127.0.0.1:9", "-q"]) == 2
    assert "cannot run on scheduler" in capsys.readouterr().err
