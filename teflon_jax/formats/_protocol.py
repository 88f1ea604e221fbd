"""The `# protocol:` line of a test record: the imposed displacement history as text."""

import dataclasses
import math
import re

import numpy as np

from ..excitation import FigureEightMotion, SineMotion, TriangleMotion
from ..units import parse_quantity, unit_factor

PROTOCOL_PATTERNS = ("sine", "triangle", "eight")


_PROTOCOL_KEY = re.compile(r"(?:^|\s)([A-Za-z_]\w*)\s*=")


@dataclasses.dataclass(frozen=True)
class Protocol:
    """The displacement history imposed in a test, as written on a `# protocol:` line.

    Text form: `<pattern> amplitude=<length> frequency=<frequency> [cycles=<number>]`, for
    example `sine amplitude=1 in frequency=0.16 Hz cycles=3` (test No. 62 of Constantinou,
    Mokha & Reinhorn 1990). Each pattern is one of the simulator's imposed motions
    (`Protocol.motion`), so a protocol line and a simulated test mean the same displacement:

    - `sine`: `teflon_jax.excitation.SineMotion`, `ux = U0 sin(2 pi frequency t)`;
    - `triangle`: `TriangleMotion`, the triangular wave of the same amplitude and period,
      starting at zero towards +x;
    - `eight`: `FigureEightMotion`, `ux = U0 sin(w t)`, `uy = U0 sin(2 w t)` with
      `w = 2 pi frequency` (Eq. 16; Figs. 5-6 of the paper).

    **Fields:**

    - `pattern`: one of `"sine"`, `"triangle"`, `"eight"`.
    - `amplitude`: `U0` [m].
    - `frequency`: cycles per second of `ux` [Hz] (`rad/s` is accepted in the text).
    - `cycles`: number of cycles imposed, or `None` when not stated.
    - `extra`: other `key=value` pairs of the line, kept as text.
    """

    pattern: str
    amplitude: float
    frequency: float
    cycles: float | None = None
    extra: dict[str, str] = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        if self.pattern not in PROTOCOL_PATTERNS:
            raise ValueError(
                f"protocol: unknown pattern '{self.pattern}'; use one of "
                f"{', '.join(PROTOCOL_PATTERNS)}."
            )
        for name in ("amplitude", "frequency"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(
                    f"protocol: {name} must be a positive number, got {value!r}."
                )
            object.__setattr__(self, name, float(value))
        if self.cycles is not None:
            if not (
                isinstance(self.cycles, (int, float))
                and math.isfinite(self.cycles)
                and self.cycles > 0
            ):
                raise ValueError(
                    f"protocol: cycles must be a positive number, got {self.cycles!r}."
                )
            object.__setattr__(self, "cycles", float(self.cycles))
        object.__setattr__(self, "extra", {str(k): str(v) for k, v in self.extra.items()})

    @property
    def duration(self) -> float | None:
        """`cycles / frequency` [s], or `None` when the number of cycles is not stated."""
        return None if self.cycles is None else self.cycles / self.frequency

    def motion(self, *, default_cycles: float = 3.0):
        """The protocol as the simulator's motion (`SineMotion`, `TriangleMotion` or
        `FigureEightMotion`), with `default_cycles` when the line states no `cycles`."""
        cycles = self.cycles if self.cycles is not None else float(default_cycles)
        if self.pattern == "sine":
            return SineMotion(self.amplitude, self.frequency, cycles=cycles)
        if self.pattern == "triangle":
            return TriangleMotion(self.amplitude, self.frequency, cycles=cycles)
        return FigureEightMotion(self.amplitude, 2.0 * np.pi * self.frequency, cycles=cycles)

    def displacement(self, time) -> tuple[np.ndarray, np.ndarray | None]:
        """Imposed displacement at `time` [s], from `Protocol.motion`.

        **Returns:** `(ux, uy)` [m] as numpy arrays; `uy` is `None` except for `eight`.
        """
        t = np.asarray(time, dtype=float)
        u = np.asarray(self.motion().displacement(t), dtype=float)
        return u[0], (u[1] if self.pattern == "eight" else None)

    def to_text(self, length_unit: str = "in", *, digits: int = 9) -> str:
        """The `# protocol:` value, with the amplitude in `length_unit`."""
        factor = unit_factor(length_unit, "length", where="protocol amplitude unit")
        parts = [
            self.pattern,
            f"amplitude={self.amplitude / factor:.{digits}g} {length_unit}",
            f"frequency={self.frequency:.{digits}g} Hz",
        ]
        if self.cycles is not None:
            parts.append(f"cycles={self.cycles:.{digits}g}")
        parts += [f"{key}={value}" for key, value in self.extra.items()]
        return " ".join(parts)


def parse_protocol(text: str, *, where: str = "protocol") -> Protocol:
    """Read a protocol line such as `sine amplitude=1 in frequency=0.16 Hz cycles=3`.

    **Arguments:**

    - `text`: the pattern followed by `key=value` pairs; `amplitude` and `frequency` need a
      unit (`1 in`, `25mm`, `0.16 Hz`, `1 rad/s`).
    - `where`: what to name in an error (the file and line).

    **Returns:** a `Protocol` in SI units.
    """
    text = text.strip()
    pattern, _, rest = text.partition(" ")
    pattern = pattern.lower()
    if pattern not in PROTOCOL_PATTERNS:
        raise ValueError(
            f"{where}: unknown protocol pattern '{pattern}'; start the line with one of "
            f"{', '.join(PROTOCOL_PATTERNS)}, e.g. "
            f"'sine amplitude=1 in frequency=0.16 Hz cycles=3'."
        )
    pieces = _PROTOCOL_KEY.split(" " + rest)
    if pieces[0].strip():
        raise ValueError(
            f"{where}: cannot read '{pieces[0].strip()}' in the protocol; write "
            f"key=value pairs, e.g. 'sine amplitude=1 in frequency=0.16 Hz cycles=3'."
        )
    values: dict[str, str] = {}
    for key, value in zip(pieces[1::2], pieces[2::2]):
        if key in values:
            raise ValueError(f"{where}: protocol key '{key}' is given twice.")
        values[key] = value.strip()
    for key in ("amplitude", "frequency"):
        if key not in values:
            raise ValueError(
                f"{where}: the protocol needs '{key}=' (e.g. "
                f"'sine amplitude=1 in frequency=0.16 Hz cycles=3')."
            )
    amplitude = parse_quantity(
        values.pop("amplitude"), "length", where=f"{where}, protocol amplitude"
    )
    frequency = parse_quantity(
        values.pop("frequency"), "frequency", where=f"{where}, protocol frequency"
    )
    cycles = None
    if "cycles" in values:
        cycles = parse_quantity(
            values.pop("cycles"), "dimensionless", where=f"{where}, protocol cycles"
        )
    try:
        return Protocol(pattern, amplitude, frequency, cycles, values)
    except ValueError as error:
        raise ValueError(f"{where}: {error}") from None
