"""Calibration of the rod-end's servo-actuator as seed 004 section 6.2 does it.

    python loadcases/library/rod_end/calibration.py [-o DIR]

1. Transmission ratio dL/dtheta and equivalent mass over the stroke (fig. 6.9): the engine
   runs the mechanism made rigid (the rod-end contact an ideal spherical joint, the two
   bushings fixed joints) in a kinematic analysis, the actuator driven at constant speed
   from -`stroke` to +`stroke`; dL/dtheta = L' / theta' (m/rad) and the equivalent mass
   m_eq = 2 T / L'^2 (kg) from the kinetic energy T of every body
   (loadcases.studies.servo_calibration.transmission).
2. Ziegler-Nichols (fig. 6.10): the library's actuator (`servo` of rod_end.mech.yaml) on
   the mean equivalent mass, proportional loop only; the ultimate gain and period from its
   step responses, then the ZN PI gains (loadcases.studies.servo_calibration.ziegler_nichols).

Prints both tables (units in every header) and, with -o DIR, writes them as
`transmission.csv` and `ziegler-nichols.csv` there.
"""

from __future__ import annotations

import argparse
import csv
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CENTRE = "[354.2105263157895, -106.93410609852879, 0]"  # the rod-end centre P (mm)
_KINEMATIC_CASE = """
case: rod-end-calibration
mechanism: {mechanism}
effects: {{hydraulics: false}}
motions:
  drive: {{joint: actuator, value: "stroke * (2 * t - 1)"}}
analysis: {{type: kinematic, end: 1.0, step: 0.01, redundant: drop}}  # the planar loop in 3-D
requests:
  travel: {{joint: actuator, quantity: travel}}
  rate:   {{joint: actuator, quantity: speed}}
  angle:  {{joint: hinge, quantity: angle}}
  omega:  {{joint: hinge, quantity: omega}}
  energy: {{quantity: energy}}
"""


def rigid_mechanism(text: str) -> str:
    """rod_end.mech.yaml made rigid: the contact `rod_end` an ideal spherical joint between
    ball and socket, the bushings `rod_socket` and `ball_surface` fixed joints (the seed's
    transmission ratio is the rigid linkage's)."""
    text = text[: text.index("\ncontacts:")] + "\n"
    joints = (
        f"  rod_end_ideal: {{type: spherical, bodies: [ball, socket], at: {CENTRE}}}\n"
        f"  socket_on_rod: {{type: fixed, bodies: [socket, rod], at: {CENTRE}}}\n"
        f"  ball_on_crank: {{type: fixed, bodies: [ball, surface], at: {CENTRE}}}\n"
    )
    text = text.replace("\nforces:\n", f"\n{joints}\nforces:\n", 1)
    for bushing in ("rod_socket", "ball_surface"):
        start = text.index(f"  {bushing}:")
        end = text.index("\n  ", text.index("torsional_damping", start)) + 1
        text = text[:start] + text[end:]
    return text


def run_transmission(folder: Path):
    """(travel (m), dL/dtheta (m/rad), m_eq (kg)) over the stroke, from the engine."""
    from loadcases.inputs.loader import load_case
    from loadcases.run import run_case
    from loadcases.studies.servo_calibration import transmission

    mech = folder / "rigid.mech.yaml"
    mech.write_text(rigid_mechanism((HERE / "rod_end.mech.yaml").read_text()))
    case = folder / "calibration.case.yaml"
    case.write_text(_KINEMATIC_CASE.format(mechanism=mech))
    outcome = run_case(load_case(case))
    if not outcome.solution.ok:
        raise RuntimeError(f"calibration run failed: {outcome.solution.message}")
    sol = outcome.solution
    rows, ratio, mass = transmission(sol, "rate.value", "omega.value", "energy.kinetic")
    return np.asarray(sol.channels["travel.value"])[rows], ratio, mass


def library_actuator():
    """The `servo` element as the library's servo cases build it."""
    from loadcases.build.model import build_run
    from loadcases.inputs.loader import load_case

    built = build_run(load_case(HERE / "extend_retract_servo.case.yaml"))
    return built.mechanism.forces["servo"]


def _write(path: Path, head: list[str], rows) -> None:
    with path.open("w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(head)
        writer.writerows(rows)


def main(argv: list[str] | None = None) -> int:
    from loadcases.studies.servo_calibration import ziegler_nichols

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, help="folder for the two CSV tables")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        travel, ratio, mass = run_transmission(Path(tmp))
    head = ["travel [mm]", "dL/dtheta [mm/deg]", "equivalent mass [kg]"]
    table = [
        (1e3 * x, 1e3 * r * np.pi / 180.0, m) for x, r, m in zip(travel, ratio, mass, strict=True)
    ]
    print(" | ".join(head))
    for row in table[:: max(len(table) // 12, 1)]:
        print(f"{row[0]:8.1f} | {row[1]:8.4f} | {row[2]:8.3f}")
    mean_mass = float(np.mean(mass))
    print(f"mean equivalent mass {mean_mass:.3f} kg (seed 6.2: the average is used)")
    zn = ziegler_nichols(library_actuator(), mean_mass, rtol=0.01)
    seed = library_actuator().controller
    zn_head = ["quantity", "value", "unit"]
    zn_rows = [
        ("ultimate gain K_u", zn.ultimate_gain, "A/m"),
        ("ultimate period T_u", zn.ultimate_period, "s"),
        ("ZN K_p = 0.45 K_u", zn.kp, "A/m"),
        ("ZN K_i = K_p / (T_u / 1.2)", zn.ki, "A/(m*s)"),
        ("library K_p (seed 6.2)", seed.kp, "A/m"),
        ("library K_i (seed 6.2)", seed.ki, "A/(m*s)"),
        ("loop evaluations", len(zn.evaluations), "-"),
    ]
    for name, value, unit in zn_rows:
        print(f"{name}: {value:.5g} {unit}")
    if args.output is not None:
        args.output.mkdir(parents=True, exist_ok=True)
        _write(args.output / "transmission.csv", head, table)
        _write(args.output / "ziegler-nichols.csv", zn_head, zn_rows)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
