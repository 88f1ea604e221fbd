"""The paper's tables as data: Table 1 (Eq. 1 constants of 16 PTFE-steel interfaces, breakaway
ratios) and Table 2 (the six-storey building), read from the cited CSV files in `data/`."""

from ._cited_table import data_dir as data_dir
from ._cited_table import read_cited_table as read_cited_table
from ._table1 import DIRECTIONS as DIRECTIONS
from ._table1 import PTFE_TYPES as PTFE_TYPES
from ._table1 import FrictionTable as FrictionTable
from ._table1 import Interface as Interface
from ._table1 import friction_table as friction_table
from ._table1 import interface_parameters as interface_parameters
from ._table1 import load_table1 as load_table1
from ._table1 import table1_parameters as table1_parameters
from ._table2 import BuildingData as BuildingData
from ._table2 import load_table2 as load_table2
