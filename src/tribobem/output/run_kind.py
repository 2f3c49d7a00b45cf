"""What the outputs know of a run's kind: read from the summary's ``kind`` and the scenario
sections the run used, never guessed from the step rows' keys.

The figures, the report and the CLI draw and print what the run kind declares
(:class:`tribobem.runs.kind.RunKind`: ``figures``, ``report_sections``, ``columns``); within a
kind, a few outputs differ by the sections the run used -- a friction kind with
``[humidity]`` does one ramp or loop per RH, a pull-off with ``[humidity]`` one pull-off per RH.
:func:`run_view` answers those questions from summary.json alone, so ``tribobem plot`` gets the
same answers from the files as the run did.

Result folders of earlier versions: ``kind`` has always been in summary.json, and so has the
scenario echo ``inputs`` with ``humidity`` (None without ``[humidity]``) since the humid runs
exist; a summary without the echo (hand-made, or older) is humid when it holds the humidity
inputs under ``problem.humidity`` or a run-level ``rh`` list.

This module imports nothing of :mod:`tribobem.runs` (a higher layer): the kind names it tests
are the registry's (:data:`tribobem.runs.KINDS`).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FRICTION_KINDS", "RunView", "run_view", "used_humidity"]

#: The tangential (friction) kinds: a normal load, then a tangential path.
FRICTION_KINDS = ("partial_slip", "hysteresis")


def used_humidity(summary: dict | None) -> bool:
    """Whether the run used the scenario section ``[humidity]`` (RH steps with menisci).

    Parameters
    ----------
    summary : dict or None
        The run summary (summary.json); None gives False.

    Returns
    -------
    bool
        From the scenario echo ``inputs.humidity`` (None: not used); for a summary without the
        echo, from ``problem.humidity`` or a run-level ``rh`` list.
    """
    s = summary or {}
    inputs = s.get("inputs")
    if isinstance(inputs, dict) and "humidity" in inputs:
        return inputs["humidity"] is not None
    if isinstance(s.get("problem"), dict) and s["problem"].get("humidity"):
        return True
    return isinstance(s.get("rh"), (list, tuple)) and len(s["rh"]) > 0


@dataclass(frozen=True)
class RunView:
    """The kind of a run and the sections it used, as the outputs need them.

    Attributes
    ----------
    kind : str or None
        summary.json ``kind`` (None when absent).
    humid : bool
        The run used ``[humidity]`` (:func:`used_humidity`).
    per_rh : bool
        The summary holds one ramp, loop or pull-off per RH with its run-level values as lists
        in RH order (``rh`` a list); False for the one-RH view of
        :func:`tribobem.output.humid.rh_summary` (``rh`` a scalar), which the dry figures and
        tables show like a dry run.
    """

    kind: str | None
    humid: bool
    per_rh: bool

    @property
    def friction(self) -> bool:
        """A tangential kind (partial_slip, hysteresis)."""
        return self.kind in FRICTION_KINDS

    @property
    def hysteresis(self) -> bool:
        """Kind ``hysteresis``: cyclic tangential loading (loops, Paper E's points, K_L)."""
        return self.kind == "hysteresis"

    @property
    def humid_friction(self) -> bool:
        """A friction kind with ``[humidity]``, its summary one ramp or loop per RH."""
        return self.friction and self.humid and self.per_rh

    @property
    def humid_pulloff(self) -> bool:
        """Kind ``pulloff`` with ``[humidity]``: one pull-off per RH."""
        return self.kind == "pulloff" and self.humid

    @property
    def rh_steps(self) -> bool:
        """Steps at RH with menisci and capillary forces: every kind run with ``[humidity]``
        (kind ``capillary`` always)."""
        return self.kind == "capillary" or self.humid

    @property
    def capillary(self) -> bool:
        """The capillary kinds' steps (one per RH with F_cap, F_ss, F_ws): kind ``capillary``
        and a humid pull-off."""
        return self.kind == "capillary" or self.humid_pulloff


def run_view(summary: dict | None) -> RunView:
    """The :class:`RunView` of a run summary (summary.json, or the one-RH view of a humid run).

    Parameters
    ----------
    summary : dict or None
        The run summary; None gives a view of no kind, dry.

    Returns
    -------
    RunView
    """
    s = summary or {}
    kind = s.get("kind")
    return RunView(kind=kind if isinstance(kind, str) else None, humid=used_humidity(s),
                   per_rh=isinstance(s.get("rh"), (list, tuple)) and len(s["rh"]) > 0)
