"""The type of a slab on groups of triple or double pendulums, for the modules that read it by
this name (`_peaks.py`): a `BidirectionalStructure` whose `bearing` is a `SeriesPendulum`
(`_series_groups.py`)."""

from ._bidirectional import BidirectionalStructure

SlabOnSeries = BidirectionalStructure
