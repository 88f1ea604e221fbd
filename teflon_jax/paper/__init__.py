"""The paper's Figs. 3-11 and report.md: `reproduce`."""

from ._reproduce import reproduce as reproduce
from ._reproduce import skipped_figures as skipped_figures
