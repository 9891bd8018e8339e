"""The benchmark models: same mechanism on both sides, consistent initial state, sane physics.

No test here measures time. The Exudyn tests are skipped when Exudyn is not installed.
"""

from __future__ import annotations

import importlib.util
import itertools
import math

import numpy as np
import pytest
import yaml

from benchmarks.accuracy import Reference, relative_error
from benchmarks.cases import case_path, case_yaml
from benchmarks.exudyn_models import ExudynOptions, run_exudyn
from benchmarks.models import (
    BodySpec,
    JointSpec,
    ModelSpec,
    OutputSpec,
    all_models,
    chain,
    consistent_velocities,
    constraint_velocity_jacobian,
    degrees_of_freedom,
    model_by_name,
)

MODELS = [m.name for m in all_models()]


@pytest.mark.parametrize(
    "name, dof",
    [
        ("slider_crank", 1),
        ("chain20", 60),
        ("fourbar10", 1),
        ("ball_bounce", 6),
        ("chain100", 300),
    ],
)
def test_mobility_and_no_redundant_equation(name: str, dof: int) -> None:
    model = model_by_name(name)
    assert degrees_of_freedom(model) == (dof, 0)


@pytest.mark.parametrize("name", MODELS)
def test_initial_velocities_satisfy_the_constraints(name: str) -> None:
    model = model_by_name(name)
    v, w = consistent_velocities(model)
    jac, _ = constraint_velocity_jacobian(model)
    x = np.hstack([v, w]).reshape(-1)
    assert np.max(np.abs(jac @ x), initial=0.0) < 1e-12
    if model.initial_rate is not None:
        joint, rate = model.initial_rate
        i = [b.name for b in model.bodies].index(model.joint(joint).bodies[0])
        assert w[i] @ np.array(model.joint(joint).axis) == pytest.approx(rate)


def test_slider_crank_initial_state_by_hand() -> None:
    """At the outer dead centre the slider stands still and the rod turns at -w r / l."""
    model = model_by_name("slider_crank")
    v, w = consistent_velocities(model)
    names = [b.name for b in model.bodies]
    assert w[names.index("crank")] == pytest.approx([0.0, 0.0, 2 * math.pi], abs=1e-12)
    assert w[names.index("rod")] == pytest.approx([0.0, 0.0, -2 * math.pi * 0.1 / 0.3], abs=1e-12)
    assert v[names.index("slider")] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)


@pytest.mark.parametrize("name", MODELS)
def test_inertia_tensors_are_physical(name: str) -> None:
    for body in model_by_name(name).bodies:
        i = body.inertia_matrix
        assert np.allclose(i, i.T)
        ev = np.linalg.eigvalsh(i)
        assert ev.min() > 0
        assert ev.max() <= ev.sum() - ev.max() + 1e-15  # triangle inequality of principal moments


@pytest.mark.parametrize("name, links", [("chain20", 20), ("chain100", 100)])
def test_chain_links_are_0_1_m_and_joined_end_to_end(name: str, links: int) -> None:
    model = model_by_name(name)
    ats = [np.array(j.at) for j in model.joints] + [np.array(model.point("tip").at)]
    lengths = [np.linalg.norm(b - a) for a, b in itertools.pairwise(ats)]
    assert lengths == pytest.approx([0.1] * links)
    assert max(abs(a[2]) for a in ats) > 0.3  # out of any vertical plane through the x axis
    assert len(model.bodies) == links and model.joints[-1].bodies == (
        f"link{links - 1}",
        f"link{links - 2}",
    )


def test_chain20_is_chain_of_20_links() -> None:
    """Generalising the chain left chain20 as it was: its spec is chain(20), 2 s."""
    assert chain(20, end=2.0, quick_end=0.5) == model_by_name("chain20")
    assert model_by_name("chain20").title == "20-link spatial chain, spherical joints, 2 s"


@pytest.mark.parametrize("name", MODELS)
def test_committed_case_file_matches_the_spec(name: str) -> None:
    model = model_by_name(name)
    assert case_path(model).read_text(encoding="utf-8") == case_yaml(model), (
        "run `python -m benchmarks.cases` to regenerate the case files"
    )


@pytest.mark.parametrize("name", MODELS)
def test_case_file_reads_back_as_the_spec(name: str) -> None:
    model = model_by_name(name)
    data = yaml.safe_load(case_path(model).read_text(encoding="utf-8"))
    mech = data["mechanism"]
    assert data["case"] == name
    assert data["analysis"]["type"] == "dynamic"
    assert data["analysis"]["end"] == model.end
    assert isinstance(data["analysis"]["tolerance"], float)
    for body in model.bodies:
        entry = mech["bodies"][body.name]
        assert entry["mass"] == body.mass
        assert entry["cm"] == list(body.cm)
        inertia = body.inertia_list()
        assert entry["inertia"] == (inertia if len(entry["inertia"]) == 6 else inertia[:3])
        assert all(isinstance(x, (int, float)) for x in entry["inertia"])
    for joint in model.joints:
        entry = mech["joints"][joint.name]
        assert entry["type"] == joint.type and entry["bodies"] == list(joint.bodies)
        assert entry["at"] == list(joint.at)
    for contact in model.contacts:
        entry = mech["contacts"][contact.name]
        assert entry["type"] == "hertz" and entry["bodies"] == [contact.body, "ground"]
        assert entry["geometry"] == {
            "shape": "sphere_plane",
            "center": list(contact.center),
            "radius": contact.radius,
            "plane_point": list(contact.plane_point),
            "normal": list(contact.normal),
        }
        assert (entry["stiffness"], entry["exponent"], entry["restitution"]) == (
            contact.stiffness,
            contact.exponent,
            contact.restitution,
        )
    columns = {o.request for o in model.outputs}
    assert set(data["requests"]) == columns


def test_relative_error_is_norm_over_columns_per_range() -> None:
    t = np.linspace(0.0, 1.0, 11)
    ref = Reference("m", t, {"a": np.sin(t), "b": 2.0 * t}, {})
    got = {"a": np.sin(t) + 0.003, "b": 2.0 * t + 0.004}
    assert relative_error(t, got, ref, ("a", "b")) == pytest.approx(0.005 / 2.0)
    assert relative_error(t, got, ref, ("b",)) == pytest.approx(0.004 / 2.0)
    # times between reference samples are interpolated linearly
    assert relative_error(np.array([0.05]), {"b": np.array([0.1])}, ref, ("b",)) == pytest.approx(
        0.0, abs=1e-15
    )


# --------------------------------------------------------------------------------------
# Exudyn side
# --------------------------------------------------------------------------------------
needs_exudyn = pytest.mark.skipif(
    importlib.util.find_spec("exudyn") is None,
    reason="Exudyn not installed (pip install -e '.[bench]')",
)


def _pendulum(rate: float | None) -> ModelSpec:
    return ModelSpec(
        name="pendulum",
        title="pendulum",
        bodies=(
            BodySpec("bob", 2.0, (0.0, -0.5, 0.0), ((0.01, 0, 0), (0, 0.01, 0), (0, 0, 0.01))),
        ),
        joints=(
            JointSpec("pin", "revolute", ("bob", "ground"), (0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0)),
        ),
        points=(),
        gravity=(0.0, -9.81, 0.0),
        end=0.05,
        quick_end=0.05,
        output_step=0.01,
        outputs=(
            OutputSpec("f", "fx", "joint_force", "pin"),
            OutputSpec("f", "fy", "joint_force", "pin"),
            OutputSpec("a", "value", "joint_angle", "pin"),
        ),
        main=("a.value",),
        initial_rate=("pin", rate) if rate is not None else None,
    )


@needs_exudyn
def test_exudyn_reaction_is_on_body_1_from_body_2_in_ground_axes() -> None:
    run = run_exudyn(_pendulum(None), ExudynOptions(step=1e-3, end=0.05))
    assert run.channels["f.fy"][-1] == pytest.approx(
        2.0 * 9.81, rel=1e-9
    )  # the pin holds the bob up
    assert run.channels["f.fx"][-1] == pytest.approx(0.0, abs=1e-9)


@needs_exudyn
def test_exudyn_joint_angle_follows_the_right_hand_rule() -> None:
    run = run_exudyn(_pendulum(1.0), ExudynOptions(step=1e-4, end=0.05))
    assert run.channels["a.value"][-1] == pytest.approx(0.05, rel=0.02)
    # swinging towards +x, the pin pulls the bob back towards -x and also carries the
    # centripetal force m w^2 l upwards
    assert run.channels["f.fx"][-1] < 0.0
    assert run.channels["f.fy"][-1] > 2.0 * 9.81


@needs_exudyn
@pytest.mark.parametrize(
    "name, step, end",
    [("slider_crank", 2.5e-4, 0.3), ("fourbar10", 1e-3, 0.3), ("chain20", 5e-4, 0.3)],
)
def test_exudyn_model_conserves_energy_and_keeps_its_joints(
    name: str, step: float, end: float
) -> None:
    model = model_by_name(name)
    run = run_exudyn(
        model,
        ExudynOptions(
            step=step, end=end, output_step=model.output_step, linear_solver="sparse", check=True
        ),
    )
    assert run.energy is not None and run.joint_gap is not None
    kinetic_scale = max(abs(run.energy[0]), 0.05 * 9.81 * sum(b.mass for b in model.bodies))
    assert np.max(np.abs(run.energy - run.energy[0])) < 1e-4 * kinetic_scale
    assert run.joint_gap.max() < 1e-8


@needs_exudyn
def test_exudyn_slider_stays_between_the_dead_centres() -> None:
    """The slider starts at the outer dead centre (0.4 m) and never passes the inner one (0.2 m)."""
    model = model_by_name("slider_crank")
    run = run_exudyn(
        model, ExudynOptions(step=2.5e-4, end=0.3, output_step=model.output_step, check=True)
    )
    x = run.channels["slider_pos.x"]
    assert x.max() <= 0.4 + 1e-9 and x.min() >= 0.2 - 1e-9
    assert x[0] == pytest.approx(0.4)
