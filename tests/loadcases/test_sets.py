"""Set compilation (run names, sweep x zip, hashes, input errors) and set execution
(serial, process pool, Dask LocalCluster; reuse; a failing run inside a set)."""

from __future__ import annotations

from pathlib import Path

import pytest

from loadcases.foundation.diagnostics import InputError
from loadcases.sets.campaign import run_set
from loadcases.sets.executors import DaskExecutor, PoolExecutor
from loadcases.sets.specs import load_and_compile_set, run_hash, run_name
from tests.loadcases.set_fixtures import write_inputs


@pytest.fixture()
def inputs(tmp_path: Path) -> Path:
    return write_inputs(tmp_path)


def test_run_name_uses_percent_g_in_si() -> None:
    assert (
        run_name("door", (("clearance", 0.0001), ("angle", 1.5707963267948966)))
        == "door[clearance=0.0001,angle=1.5708]"
    )
    assert run_name("door", ()) == "door"


def test_sweep_is_a_cartesian_product_in_listed_order(inputs: Path) -> None:
    compiled = load_and_compile_set(inputs / "crank.set.yaml")
    assert [r.name for r in compiled.runs] == [
        f"crank-turn[speed={s},load={f}N]" for s in (1, 2, 3) for f in (10, 20)
    ]
    first = compiled.runs[0]
    assert dict(first.parameters) == {"speed": 1.0, "load": 10.0, "stroke": 0.05}
    assert len({r.input_sha256 for r in compiled.runs}) == 6


def test_zip_varies_together_and_combines_with_sweep(inputs: Path) -> None:
    (inputs / "z.set.yaml").write_text(
        "set: z\ncases: [crank.case.yaml]\nzip: {load: [1, 2], speed: [3, 4]}\n"
        "parameters: {stroke: 0.01}\n",
        encoding="utf-8",
    )
    names = [r.name for r in load_and_compile_set(inputs / "z.set.yaml").runs]
    assert names == ["crank-turn[load=1,speed=3]", "crank-turn[load=2,speed=4]"]
    (inputs / "zs.set.yaml").write_text(
        "set: zs\ncases: [crank.case.yaml]\nzip: {load: [1, 2]}\nsweep: {speed: [3, 4]}\n",
        encoding="utf-8",
    )
    names = [r.name for r in load_and_compile_set(inputs / "zs.set.yaml").runs]
    assert names == [
        "crank-turn[load=1,speed=3]",
        "crank-turn[load=2,speed=3]",
        "crank-turn[load=1,speed=4]",
        "crank-turn[load=2,speed=4]",
    ]


def test_case_without_the_swept_parameter_runs_once(inputs: Path) -> None:
    compiled = load_and_compile_set(inputs / "slider.set.yaml")
    assert [r.name for r in compiled.runs] == [
        "slider-push[stroke=0.05]",
        "slider-push[stroke=0.2]",
        "crank-turn",
    ]


def test_input_hash_covers_parameters_and_version() -> None:
    base = run_hash("a" * 64, (("p", 1.0),), "1.0")
    assert base != run_hash("a" * 64, (("p", 1.5),), "1.0")
    assert base != run_hash("a" * 64, (("p", 1.0),), "1.1")
    assert base != run_hash("b" * 64, (("p", 1.0),), "1.0")


def test_unknown_parameter_is_an_input_error_with_position_and_hint(inputs: Path) -> None:
    (inputs / "bad.set.yaml").write_text(
        "set: bad\ncases: [crank.case.yaml]\nsweep:\n  sped: [1, 2]\n"
        "allowables: {drive_torqe.value: {max: 1}}\n",
        encoding="utf-8",
    )
    with pytest.raises(InputError) as error:
        load_and_compile_set(inputs / "bad.set.yaml")
    text = str(error.value)
    assert f"{inputs / 'bad.set.yaml'}:4:3: error: sweep.sped: unknown parameter 'sped'" in text
    assert "did you mean 'speed'" in text
    assert "unknown request 'drive_torqe'" in text and "did you mean 'drive_torque'" in text


def _tables(directory: Path) -> dict[str, str]:
    return {
        p.relative_to(directory).as_posix(): p.read_text() for p in sorted(directory.rglob("*.csv"))
    }


def test_pool_and_dask_give_identical_results(inputs: Path) -> None:
    serial = run_set(inputs / "crank.set.yaml", output_dir=inputs / "serial")
    pool = run_set(inputs / "crank.set.yaml", output_dir=inputs / "pool", executor=PoolExecutor(2))
    dask = run_set(
        inputs / "crank.set.yaml",
        output_dir=inputs / "dask",
        executor=DaskExecutor(
            "local",
            jobs=1,
            cluster_options={"processes": False, "protocol": "tcp://", "host": "127.0.0.1"},
        ),
    )
    tables = _tables(serial.directory)
    assert len(tables) == 9 and {"envelope.csv", "margins.csv", "loads-matrix.csv"} <= set(tables)
    assert _tables(pool.directory) == tables == _tables(dask.directory)
    assert [r.name for r in dask.records] == [r.name for r in serial.records]
    assert all(r.ok and not r.reused for r in pool.records)


def test_unchanged_runs_are_reused_and_force_recomputes(inputs: Path) -> None:
    out = inputs / "out"
    first = run_set(inputs / "crank.set.yaml", output_dir=out)
    envelope = (first.directory / "envelope.csv").read_text()
    again = run_set(inputs / "crank.set.yaml", output_dir=out)
    assert all(r.reused for r in again.records)
    assert (again.directory / "envelope.csv").read_text() == envelope
    set_text = (inputs / "crank.set.yaml").read_text()
    (inputs / "crank.set.yaml").write_text(set_text.replace("[1.0, 2.0, 3.0]", "[1.0, 2.5, 3.0]"))
    changed = run_set(inputs / "crank.set.yaml", output_dir=out)
    assert [r.reused for r in changed.records] == [True, True, False, False, True, True]
    forced = run_set(inputs / "crank.set.yaml", output_dir=out, force=True)
    assert not any(r.reused for r in forced.records)


def test_a_failing_run_does_not_stop_the_set(inputs: Path) -> None:
    result = run_set(inputs / "slider.set.yaml", output_dir=inputs / "out")
    assert [(r.name, r.status) for r in result.records] == [
        ("slider-push[stroke=0.05]", "ok"),
        ("slider-push[stroke=0.2]", "failed"),
        ("crank-turn", "ok"),
    ]
    assert "cannot be assembled" in result.failed[0].message
    assert all(
        row.max_run != "slider-push[stroke=0.2]" and row.min_run != "slider-push[stroke=0.2]"
        for row in result.envelope
    )
    summary = result.directory / "slider-push[stroke=0.2].summary.json"
    assert '"status": "failed"' in summary.read_text()
    again = run_set(inputs / "slider.set.yaml", output_dir=inputs / "out")
    assert [r.reused for r in again.records] == [True, False, True]
