"""File formats: the test-record CSV, the protocol line, PEER AT2 and column files, the friction-damper
JSON, the bundled-record catalogue, study results, target spectra and pelicun demand samples. File I/O only; nothing here is traced."""

from ._at2 import read_at2 as read_at2
from ._bearing_file import BEARING_PARTS as BEARING_PARTS
from ._bearing_file import bearing_from_dict as bearing_from_dict
from ._bearing_file import bearing_to_dict as bearing_to_dict
from ._bearing_file import load_bearing as load_bearing
from ._bearing_file import load_bearing_posterior as load_bearing_posterior
from ._bearing_file import save_bearing as save_bearing
from ._bearing_posterior import MIN_POSTERIOR_ESS as MIN_POSTERIOR_ESS
from ._bearing_posterior import POSTERIOR_FIELDS as POSTERIOR_FIELDS
from ._bearing_posterior import BearingPosterior as BearingPosterior
from ._bearing_posterior import thinned_posterior as thinned_posterior
from ._columns import read_single_column as read_single_column
from ._columns import read_two_column as read_two_column
from ._damper import read_friction_damper_json as read_friction_damper_json
from ._external import external_data_dir as external_data_dir
from ._external import load_record as load_record
from ._isolator_file import isolator_from_dict as isolator_from_dict
from ._isolator_file import load_isolator as load_isolator
from ._isolator_write import isolator_to_dict as isolator_to_dict
from ._isolator_write import write_isolator as write_isolator
from ._pelicun import PELICUN_UNITS as PELICUN_UNITS
from ._pelicun import check_pelicun_path as check_pelicun_path
from ._pelicun import pelicun_demand_table as pelicun_demand_table
from ._pelicun import write_pelicun_demands as write_pelicun_demands
from ._protocol import Protocol as Protocol
from ._protocol import parse_protocol as parse_protocol
from ._spectrum_file import read_target_spectrum as read_target_spectrum
from ._test_record import INTERFACE_KEYS as INTERFACE_KEYS
from ._test_record import TestRecord as TestRecord
from ._test_record import interface_counts as interface_counts
from ._test_record import test_record_from_arrays as test_record_from_arrays
from ._test_record_csv import read_motion_record as read_motion_record
from ._test_record_csv import read_test_record as read_test_record
from ._test_record_csv import write_test_record as write_test_record
