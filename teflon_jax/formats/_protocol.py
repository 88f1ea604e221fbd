"""The `# protocol:` line of a test record: the imposed displacement history as text."""

import dataclasses
import math
import re

import numpy as np

from ..units import parse_quantity, unit_factor

PROTOCOL_PATTERNS = ("sine", "triangle", "eight")


_PROTOCOL_KEY = re.compile(r"(?:^|\s)([A-Za-z_]\w*)\s*=")


@dataclasses.dataclass(frozen=True)
class Protocol:
    """The displacement history imposed in a test, as written on a `# protocol:` line.

    Text form: `<pattern> amplitude=<length> frequency=<frequency> [cycles=<number>]`, for
    example `sine amplitude=1 in frequency=0.16 Hz cycles=3` (test No. 62 of Constantinou,
    Mokha & Reinhorn 1990). Patterns, with `w = 2 pi frequency` and `U0 = amplitude`:

    - `sine`: `ux = U0 sin(w t)`;
    - `triangle`: a triangular wave of the same amplitude and period, starting at zero and
      moving towards +x (constant velocity `4 U0 frequency` between reversals);
    - `eight`: the figure-eight orbit `ux = U0 sin(w t)`, `uy = U0 sin(2 w t)` (Figs. 5-6 of
      the paper).

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

    def displacement(self, time) -> tuple[np.ndarray, np.ndarray | None]:
        """Imposed displacement at `time` [s].

        **Returns:** `(ux, uy)` [m]; `uy` is `None` except for the `eight` pattern.
        """
        t = np.asarray(time, dtype=float)
        omega = 2.0 * np.pi * self.frequency
        if self.pattern == "triangle":
            # Triangle wave of unit amplitude, phase-aligned with sin(w t).
            phase = (self.frequency * t + 0.25) % 1.0
            ux = self.amplitude * (1.0 - 4.0 * np.abs(phase - 0.5))
            return ux, None
        ux = self.amplitude * np.sin(omega * t)
        if self.pattern == "eight":
            return ux, self.amplitude * np.sin(2.0 * omega * t)
        return ux, None

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
