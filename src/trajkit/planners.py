"""The catalog of joint-move planners: what each one takes, read by every front end.

``trajkit plan``, a scenario's ``joint_move`` task and a sweep's ``planner`` are
all built from :data:`CATALOG`, so a name, a unit or a rule is written once:

- each planner's **inputs** (boundary states, durations) and **limits** are
  :data:`QUANTITIES`, named as the Python keyword is named (``vmax``, ``a0``,
  ``min_duration``) in the command line (``--vmax``), scenario files and sweep files
  alike; angular ones may be given in degrees at the edges (``--deg``, ``q0_deg``);
- its **options** are :data:`OPTIONS` (``sync``, ``grid``), their choices listed once;
- ``period``, the controller period, is a separate thing from any sampling step:
  a planner that takes it puts its switching times on the period's multiples.

Adding a planner is its function and one :class:`Planner` entry here; the test of
the catalog checks that every entry is reachable from the command line, scenario
files and sweeps, and that the same input gives the same trajectory through each.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from trajkit.errors import InvalidInputError
from trajkit.profiles.limited import GRIDS, SYNC_NAMES
from trajkit.profiles.polynomial import cubic, quintic, septic
from trajkit.profiles.scurve import scurve
from trajkit.profiles.trapezoidal import trapezoidal
from trajkit.trajectory import Trajectory

__all__ = ["CATALOG", "LIMITS", "OPTIONS", "QUANTITIES", "Option", "Planner", "Quantity"]


@dataclass(frozen=True)
class Quantity:
    """One number per joint (or one per move) that a planner takes.

    Attributes
    ----------
    name : str
        The Python keyword, and the key of every front end (``--min-duration`` on
        the command line, ``_`` becoming ``-``).
    unit : str
        Its SI unit for a revolute joint (``rad/s``); a prismatic joint's is in m.
    meaning : str
        What it is, in a few words, for help texts.
    per_joint : bool
        One value per joint (a single one applies to all) or one for the move.
    angular : bool
        Converted from degrees where the user writes degrees.
    default : float or None
        The planner's own value when left out (None: there is none, or the planner
        works without it).
    """

    name: str
    unit: str
    meaning: str
    per_joint: bool = True
    angular: bool = True
    default: float | None = None


#: Every input and limit of the catalog's planners.
QUANTITIES: dict[str, Quantity] = {
    q.name: q
    for q in (
        Quantity("q0", "rad", "start positions"),
        Quantity("qf", "rad", "end positions"),
        Quantity("v0", "rad/s", "start velocities", default=0.0),
        Quantity("vf", "rad/s", "end velocities", default=0.0),
        Quantity("a0", "rad/s^2", "start accelerations", default=0.0),
        Quantity("af", "rad/s^2", "end accelerations", default=0.0),
        Quantity("duration", "s", "move time; by default the shortest under the limits",
                 per_joint=False, angular=False),
        Quantity("min_duration", "s", "a floor on the move time", per_joint=False,
                 angular=False),
        Quantity("vmax", "rad/s", "velocity limits"),
        Quantity("amax", "rad/s^2", "acceleration limits"),
        Quantity("jmax", "rad/s^3", "jerk limits"),
    )
}  # fmt: skip

#: The quantities that are limits: they bound the plan and are what it is checked against.
LIMITS = ("vmax", "amax", "jmax")


@dataclass(frozen=True)
class Option:
    """A named choice of a planner, with its default and the choices it has."""

    name: str
    default: str
    choices: tuple[str, ...]
    meaning: str


#: Every option of the catalog's planners.
OPTIONS: dict[str, Option] = {
    o.name: o
    for o in (
        Option("sync", "time", tuple(name for name in SYNC_NAMES if name is not None),
               "time: the joints finish together; phase: they move on a line; "
               "time_if_necessary: together unless ending at rest; none: each as fast as "
               "it can"),
        Option("grid", "switches", GRIDS,
               "with a controller period: put every switching time (switches) or only "
               "the duration (duration) on its multiples"),
    )
}  # fmt: skip


@dataclass(frozen=True)
class Planner:
    """One catalog entry: a joint-move planner and everything it takes.

    Attributes
    ----------
    name : str
        Its name on the command line, in scenario files and in sweep files.
    law : callable
        The Python function: ``law(q0=, qf=, **inputs, **limits, **options)``.
    summary : str
        One line for help texts.
    inputs : tuple of str
        The :data:`QUANTITIES` it takes besides ``q0`` and ``qf``, limits excluded.
    limits : tuple of str
        The :data:`LIMITS` it takes.
    needs : tuple of str
        The limits it cannot plan without.
    options : tuple of str
        The :data:`OPTIONS` it takes.
    period : bool
        Whether it takes a controller period (switching times on its multiples).
    batch : str or None
        The :mod:`trajkit.batch` function that plans many such moves at once.
    """

    name: str
    law: Callable[..., Trajectory]
    summary: str
    inputs: tuple[str, ...]
    limits: tuple[str, ...]
    needs: tuple[str, ...] = ()
    options: tuple[str, ...] = ()
    period: bool = False
    batch: str | None = None

    def takes(self, name: str) -> bool:
        """Whether ``name`` (a quantity, an option or ``period``) applies to this planner."""
        if name == "period":
            return self.period
        return name in ("q0", "qf") or name in self.inputs + self.limits + self.options

    def refusal(self, name: str) -> str:
        """Why ``name`` is refused: ``"applies to the ..., not cubic"``, to follow a key."""
        users = [entry.name for entry in CATALOG.values() if entry.takes(name)]
        listed = ", ".join(users[:-1]) + f" and {users[-1]}" if len(users) > 1 else users[0]
        return f"applies to the {listed} planners, not {self.name}"

    def plan(self, values: Mapping[str, Any], *, period: float | None = None) -> Trajectory:
        """Plan one move from ``values`` (quantity and option names; SI units).

        A value of None is left out, so the planner's default applies. ``period`` is the
        controller period (s).

        Raises
        ------
        InvalidInputError
            A value this planner does not take, a limit it needs left out, or what
            the planner itself refuses.
        """
        kwargs = {key: value for key, value in values.items() if value is not None}
        self.check(kwargs)
        if period is not None:
            if not self.period:
                raise InvalidInputError(f"a controller period {self.refusal('period')}")
            kwargs["period"] = period
        elif "grid" in kwargs:
            raise InvalidInputError("grid needs a controller period (the grid is its ticks)")
        return self.law(**kwargs)

    def check(self, given: Mapping[str, Any]) -> None:
        """Refuse a value this planner does not take, or a limit it needs left out."""
        for key in given:
            if not self.takes(key):
                raise InvalidInputError(f"{key} {self.refusal(key)}")
        for key in ("q0", "qf", *self.needs):
            if given.get(key) is None:
                raise InvalidInputError(f"{key}: required by the {self.name} planner")
        if given.get("duration") is not None and given.get("min_duration") is not None:
            raise InvalidInputError("give duration (exact) or min_duration (a floor), not both")


_POLYNOMIAL_INPUTS = ("duration", "v0", "vf")

#: The planners by name, as the command line, scenario files and sweeps know them.
CATALOG: dict[str, Planner] = {
    p.name: p
    for p in (
        Planner("cubic", cubic, "cubic polynomial: positions and velocities at both ends",
                _POLYNOMIAL_INPUTS, LIMITS),
        Planner("quintic", quintic, "quintic polynomial: accelerations at both ends too",
                (*_POLYNOMIAL_INPUTS, "a0", "af"), LIMITS),
        Planner("septic", septic, "septic polynomial: jerks zero at both ends",
                (*_POLYNOMIAL_INPUTS, "a0", "af"), LIMITS),
        Planner("trapezoid", trapezoidal, "time-optimal trapezoidal velocity profile",
                ("duration", "min_duration", "v0", "vf"), ("vmax", "amax"),
                needs=("vmax", "amax"), options=("sync", "grid"), period=True,
                batch="trapezoidal"),
        Planner("scurve", scurve, "time-optimal jerk-limited (S-curve) profile",
                ("duration", "min_duration", "v0", "vf", "a0", "af"), LIMITS, needs=LIMITS,
                options=("sync", "grid"), period=True, batch="scurve"),
    )
}  # fmt: skip
