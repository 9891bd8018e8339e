"""Counting the accepted steps the compiled whole runs take (genalpha run.StepRun.run)."""

from __future__ import annotations

from typing import Any

from mechlib.solvers.genalpha import run as genalpha_run


def count_kernel_steps(patch: Any) -> dict[str, int]:
    """Patches StepRun.run (with `patch`, a pytest MonkeyPatch or its context) to add the
    accepted steps each call takes to the returned dict's "steps"."""
    taken = {"steps": 0}
    original = genalpha_run.StepRun.run

    def run(self, s, *args):
        before = self.stepper.stats.steps
        found = original(self, s, *args)
        taken["steps"] += self.stepper.stats.steps - before
        return found

    patch.setattr(genalpha_run.StepRun, "run", run)
    return taken
