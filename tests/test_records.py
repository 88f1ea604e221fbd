"""Test-record CSV (FORMATS.md): read, write, validation; the friction damper JSON."""

import json

import numpy as np
import pytest

import teflon_jax.formats as records
from teflon_jax.formats import (
    Protocol,
    parse_protocol,
    read_friction_damper_json,
    read_test_record,
    write_test_record,
)

# Independent conversion factors (exact by definition), not taken from teflon_jax._units.
M_PER_IN = 0.0254
N_PER_LBF = 0.45359237 * 9.80665
N_PER_KIP = 1000.0 * N_PER_LBF
PA_PER_PSI = N_PER_LBF / M_PER_IN**2

DAMPER_FILE = "friction_damper_brfd_arts_lab/1Hz30lbtension1amplitude.json"


def _synthetic_record(*, biaxial=True, with_n=True):
    time = np.linspace(0.0, 6.25, 401)
    omega = 2.0 * np.pi * 0.16
    ux = 0.0254 * np.sin(omega * time)
    uy = 0.0127 * np.sin(2.0 * omega * time)
    fx = 9.0e3 * np.tanh(np.cos(omega * time) / 0.05)
    fy = -4.0e3 * np.tanh(np.cos(2.0 * omega * time) / 0.05)
    normal_load = 3.49e5 * (1.0 + 0.01 * np.sin(3.0 * time))
    metadata = {
        "specimen": "PTFE-steel flat slider, unfilled sheet PTFE",
        "contact_area": 0.0506,
        **({} if with_n else {"normal_load": 3.49e5}),
        "direction": "P",
        "interfaces_in_parallel": 2,
        "interfaces_in_series": 3,
        "ptfe": "UF",
        "source": "synthetic",
        "lab_id": "T-62 rerun",
        "speed [in/s]": "1.0",
        "comment": "first line\nsecond line",
    }
    return records.test_record_from_arrays(
        ux,
        fx,
        time=time,
        uy=uy if biaxial else None,
        fy=fy if biaxial else None,
        normal_load=normal_load if with_n else None,
        temperature=20.0 + 0.5 * time,
        metadata=metadata,
        extra_columns={"velocity": np.gradient(ux, time), "gauge": 3.0 * time + 1.0},
        extra_units={"velocity": "m/s", "gauge": "mV"},
    )


def _assert_same(a, b, rtol=5e-9):
    for name in ("time", "ux", "fx", "uy", "fy", "normal_load", "temperature"):
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            np.testing.assert_allclose(y, x, rtol=rtol, atol=1e-12 * np.max(np.abs(x)))
    assert a.extra_units == b.extra_units
    assert a.extra_columns.keys() == b.extra_columns.keys()
    for name, x in a.extra_columns.items():
        np.testing.assert_allclose(b.extra_columns[name], x, rtol=rtol, atol=1e-12)
    assert a.metadata.keys() == b.metadata.keys()
    for key, value in a.metadata.items():
        if isinstance(value, float):
            assert b.metadata[key] == pytest.approx(value, rel=rtol)
        else:
            assert b.metadata[key] == value, key


@pytest.mark.parametrize("units", [None, "SI", {"length": "mm", "force": "kN"}])
def test_round_trip(tmp_path, units):
    record = _synthetic_record()
    path = tmp_path / "record.csv"
    write_test_record(path, record, units=units)
    back = read_test_record(path)
    _assert_same(record, back)
    assert back.path == path
    assert back.is_biaxial and not back.is_digitised
    header = next(
        line for line in path.read_text().splitlines() if not line.startswith("#")
    )
    expected = (
        "ux [mm]" if isinstance(units, dict) else {None: "ux [in]", "SI": "ux [m]"}[units]
    )
    assert expected in header
    assert "gauge [mV]" in header


def test_written_numbers_are_in_the_chosen_units(tmp_path):
    # 1 in and 1 kip at t = 0.5 s must read "1" in the file in paper units.
    record = records.test_record_from_arrays(
        [0.0, M_PER_IN], [0.0, N_PER_KIP], time=[0.0, 0.5], normal_load=78.5 * N_PER_KIP
    )
    path = tmp_path / "paper.csv"
    write_test_record(path, record)
    lines = path.read_text().splitlines()
    assert lines[0] == "time [s],ux [in],fx [kip],N [kip]"
    assert lines[2] == "0.5,1,1,78.5"
    write_test_record(path, record, units="SI")
    assert path.read_text().splitlines()[2].split(",")[1] == "0.0254"


def test_constant_normal_load_is_written_as_metadata(tmp_path):
    record = _synthetic_record(biaxial=False, with_n=False)
    np.testing.assert_array_equal(record.normal_load, 3.49e5)
    path = tmp_path / "uniaxial.csv"
    write_test_record(path, record)
    text = path.read_text()
    assert "N [" not in text and "# normal_load [kip]:" in text
    back = read_test_record(path)
    _assert_same(record, back)
    assert not back.is_biaxial


def test_read_paper_units_against_hand_conversion(tmp_path):
    path = tmp_path / "test62.csv"
    path.write_text(
        "# specimen: PTFE-steel flat slider\n"
        "# contact_area [in^2]: 78.5\n"
        "# direction: P\n"
        "# interfaces_in_parallel: 2\n"
        "# ptfe: UF\n"
        "# mystery_key [furlong]: 3\n"
        "# operator: A. N. Other\n"
        "fx [kip],N [kip],time [s], ux [in],temperature [degC],strain [ue]\n"
        "0.000,78.5,0.00,0.0000,21.5,5\n"
        "1.204,78.5,0.01,0.0025,21.5,7\n"
    )
    record = read_test_record(path)
    np.testing.assert_allclose(record.time, [0.0, 0.01])
    np.testing.assert_allclose(record.ux, [0.0, 0.0025 * M_PER_IN], rtol=1e-14)
    np.testing.assert_allclose(record.fx, [0.0, 1.204 * N_PER_KIP], rtol=1e-12)
    np.testing.assert_allclose(record.normal_load, 78.5 * N_PER_KIP, rtol=1e-12)
    np.testing.assert_allclose(record.temperature, 21.5)
    assert record.metadata["contact_area"] == pytest.approx(78.5 * M_PER_IN**2, rel=1e-14)
    # 78.5 kip on 78.5 in^2 is 1000 psi, the pressure of test No. 62.
    np.testing.assert_allclose(record.contact_pressure, 1000.0 * PA_PER_PSI, rtol=1e-12)
    assert record.metadata["direction"] == "P"
    assert record.metadata["interfaces_in_parallel"] == 2
    assert record.metadata["ptfe"] == "UF"
    assert record.metadata["mystery_key [furlong]"] == "3"
    assert record.metadata["operator"] == "A. N. Other"
    np.testing.assert_array_equal(record.extra_columns["strain"], [5.0, 7.0])
    assert record.extra_units["strain"] == "ue"
    assert record.uy is None and record.fy is None and not record.is_biaxial


def test_normal_load_from_area_and_pressure_or_none(tmp_path):
    path = tmp_path / "pressure.csv"
    path.write_text(
        "# contact_area [in^2]: 50\n# pressure [psi]: 2000\n"
        "time [s],ux [mm],fx [N]\n0,0,0\n1,1,10\n"
    )
    record = read_test_record(path)
    np.testing.assert_allclose(record.normal_load, 1.0e5 * N_PER_LBF, rtol=1e-12)
    np.testing.assert_allclose(record.contact_pressure, 2000.0 * PA_PER_PSI, rtol=1e-12)
    np.testing.assert_allclose(record.ux, [0.0, 1.0e-3])

    path.write_text("# contact_area [in^2]: 50\ntime [s],ux [mm],fx [N]\n0,0,0\n1,1,10\n")
    record = read_test_record(path)
    assert record.normal_load is None and record.contact_pressure is None


def test_metadata_quantity_with_unit_in_value(tmp_path):
    path = tmp_path / "value_unit.csv"
    path.write_text("# normal_load: 78.5kip\ntime [s],ux [in],fx [kip]\n0,0,0\n")
    record = read_test_record(path)
    np.testing.assert_allclose(record.normal_load, [78.5 * N_PER_KIP], rtol=1e-12)


_GOOD_HEADER = "time [s],ux [in],fx [kip]\n"


@pytest.mark.parametrize(
    "text, expected",
    [
        ("time [s],ux,fx [kip]\n0,0,0\n", ["line 1", "'ux'", "no unit"]),
        ("time [s],ux [furlong],fx [kip]\n0,0,0\n", ["line 1", "'ux'", "furlong"]),
        ("time [s],ux [in],fx [in]\n0,0,0\n", ["line 1", "'fx'", "length"]),
        ("time [s],ux [in],fx [kip],N [psi]\n0,0,0,1\n", ["line 1", "'N'", "pressure"]),
        (_GOOD_HEADER + "0,0,0\n0.1,nan,0\n", ["line 3", "'ux'", "nan"]),
        (_GOOD_HEADER + "0,0,0\n0.1,0.2,\n", ["line 3", "'fx'", "empty"]),
        (_GOOD_HEADER + "0,0,0\n0.1,0.2\n", ["line 3", "2 cell", "3 columns"]),
        (_GOOD_HEADER + "0,0,0\n0.1,0.2,0.3,0.4\n", ["line 3", "4 cell"]),
        (_GOOD_HEADER + "0,0,0\n0.1,abc,1\n", ["line 3", "'ux'", "'abc'"]),
        (_GOOD_HEADER + "0,0,0\n0.1,0,1\n0.1,0,1\n", ["line 4", "'time'", "increase"]),
        (_GOOD_HEADER + "0,0,0\n0.2,0,1\n0.1,0,1\n", ["line 4", "'time'", "increase"]),
        (_GOOD_HEADER + "0,0,0\n\n0.2,0,1\n", ["line 3", "empty line"]),
        (_GOOD_HEADER + "0,0,0\n# late: 1\n", ["line 3", "before the header"]),
        ("time [s],ux [in]\n0,0\n", ["line 1", "'fx'", "missing"]),
        ("ux [in],fx [kip]\n0,0\n", ["protocol"]),
        ("# direction: Q\n" + _GOOD_HEADER + "0,0,0\n", ["line 1", "direction"]),
        ("# ptfe: PEEK\n" + _GOOD_HEADER + "0,0,0\n", ["line 1", "ptfe", "UF"]),
        (
            "# x: 1\n# interfaces_in_series: two\n" + _GOOD_HEADER + "0,0,0\n",
            ["line 2", "interfaces_in_series"],
        ),
        (
            "# interfaces: 2\n" + _GOOD_HEADER + "0,0,0\n",
            ["line 1", "ambiguous", "interfaces_in_parallel", "interfaces_in_series"],
        ),
        ("# contact_area: 78.5\n" + _GOOD_HEADER + "0,0,0\n", ["line 1", "no unit"]),
        ("# contact_area [kip]: 1\n" + _GOOD_HEADER + "0,0,0\n", ["line 1", "area"]),
        ("# normal_load [kip]: -5\n" + _GOOD_HEADER + "0,0,0\n", ["line 1", "positive"]),
        ("# ptfe: UF\n# normal_load [kip]: 100\ntime [s],ux [in],fx [kip],N [kN]\n0,0,0,444.822162\n"
         "0.1,0,1,400\n", ["line 2: '# normal_load [kip]: 100' contradicts the N column ('N [kN]'), which "
                           "holds 400 on line 5", "remove the metadata line or make the two agree"]),
        ("# contact_area [in^2]: 50\n# pressure [psi]: 2000\ntime [s],ux [in],fx [kip],N [kip]\n0,0,0,100\n"
         "0.1,0,1,90\n", ["lines 1, 2 and 5: '# contact_area [in^2]: 50' times '# pressure [psi]: 2000' is a normal "
                          "load of 100 kip, but the N column ('N [kip]') holds 90 on line 5", "to 1e-6 of it",
                          "remove the pressure line", "or correct the contact area or the pressure"]),
        ("# pressure: 2000psi\n# ptfe: UF\n# normal_load [kN]: 400\n# contact_area [in^2]: 50\n" + _GOOD_HEADER
         + "0,0,0\n", ["lines 1, 3 and 4: '# contact_area [in^2]: 50' times '# pressure: 2000psi' is a normal load "
                       "of 444.822162 kN, but line 3 states '# normal_load [kN]: 400'", "to 1e-6 of it",
                       "'# normal_load' is the load used"]),
        ("time [s],ux [in],fx [kip],N [kip]\n0,0,0,500\n0.1,0.2,1,-5\n",
         ["line 3", "'N'", "must be > 0", "got -5 kip"]),
        ("time [s],ux [in],fx [kip],N [kN]\n0,0,0,0\n", ["line 2", "'N'", "got 0 kN"]),
        ("# a: 1\n# a: 2\n" + _GOOD_HEADER + "0,0,0\n", ["line 2", "twice"]),
        (
            "# protocol: sine amplitude=1 in\nux [in],fx [kip]\n0,0\n",
            ["line 1", "frequency"],
        ),
        (
            "# protocol: wobble amplitude=1 in frequency=1 Hz\nux [in],fx [kip]\n0,0\n",
            ["line 1", "wobble"],
        ),
        (
            "# protocol: sine amplitude=1 frequency=1 Hz\nux [in],fx [kip]\n0,0\n",
            ["line 1", "amplitude", "no unit"],
        ),
        ("time [s];ux [in];fx [kip]\n0;0;0\n", ["line 1", "','"]),
        ("time [s],ux [in],ux [in],fx [kip]\n0,0,0,0\n", ["line 1", "twice"]),
        ("# only: metadata\n", ["no header"]),
        (_GOOD_HEADER, ["no data rows"]),
    ],
)
def test_bad_input_is_reported_with_its_place(tmp_path, text, expected):
    path = tmp_path / "bad_record.csv"
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        read_test_record(path)
    message = str(info.value)
    assert "bad_record.csv" in message
    for piece in expected:
        assert piece in message, (piece, message)


def test_a_normal_load_line_that_agrees_with_the_n_column_is_read(tmp_path):
    path = tmp_path / "agree.csv"
    path.write_text("# normal_load [kip]: 100\ntime [s],ux [in],fx [kip],N [kN]\n0,0,0,444.822162\n"
                    "0.1,0,1,444.8222\n")
    np.testing.assert_allclose(read_test_record(path).normal_load, 444822.162, rtol=1e-6)


def test_a_normal_load_the_history_contradicts_is_not_written(tmp_path):
    record = _synthetic_record()
    record = records.test_record_from_arrays(record.ux, record.fx, time=record.time, normal_load=record.normal_load,
                                             metadata={"normal_load": 3.49e5})
    with pytest.raises(ValueError, match="metadata 'normal_load' .349000 N. contradicts the normal-load history"):
        write_test_record(tmp_path / "r.csv", record)


def test_a_contact_area_and_pressure_that_agree_with_the_normal_load_are_read(tmp_path):
    path = tmp_path / "agree.csv"
    path.write_text("# contact_area [in^2]: 50\n# pressure [psi]: 2000\n# normal_load [kip]: 100\n"
                    "time [s],ux [in],fx [kip],N [kN]\n0,0,0,444.822162\n0.1,0,1,444.8222\n")
    record = read_test_record(path)
    np.testing.assert_allclose(record.normal_load, 1.0e5 * N_PER_LBF, rtol=1e-6)
    path.write_text("# contact_area [in^2]: 50\n# pressure [psi]: 2000\n# normal_load: 100.00005kip\n"
                    + _GOOD_HEADER + "0,0,0\n")
    np.testing.assert_allclose(read_test_record(path).normal_load, 1.0e5 * N_PER_LBF, rtol=1e-6)


@pytest.mark.parametrize("normal_load, metadata, words", [
    (1.1e5, {}, "is 100000 N, but the normal-load history (column N) is 110000 N, more than 1e-6 of it apart"),
    (None, {"normal_load": 1.2e5}, "is 100000 N, but metadata 'normal_load' is 120000 N"),
])
def test_a_contact_pressure_the_normal_load_contradicts_is_not_written(tmp_path, normal_load, metadata, words):
    time = np.linspace(0.0, 1.0, 5)
    record = records.test_record_from_arrays(time, time, time=time, normal_load=normal_load, metadata={
        "contact_area": 0.05, "contact_pressure": 2e6, **metadata})
    with pytest.raises(ValueError) as error:
        write_test_record(tmp_path / "r.csv", record)
    assert "record: metadata 'contact_area' (0.05 m^2) times 'contact_pressure' (2e+06 Pa) " + words in str(error.value)
    assert "drop 'contact_pressure' from the metadata or make the two agree" in str(error.value)
    assert not (tmp_path / "r.csv").exists()


@pytest.mark.parametrize("normal_load, metadata", [
    (None, {"normal_load": 78.54 * 1234.5 * N_PER_LBF}),
    (78.54 * 1234.5 * N_PER_LBF * (1.0 + 4e-7 * np.sin(np.arange(5.0))), {}),
])
def test_what_the_writer_writes_with_few_digits_the_reader_reads(tmp_path, normal_load, metadata):
    # contact_area x contact_pressure equals the load to 1e-6, but the three numbers rounded to a
    # few digits each do not: the writer refuses (naming digits) rather than write a file the
    # reader refuses, and with enough digits the file reads back
    time = np.linspace(0.0, 1.0, 5)
    record = records.test_record_from_arrays(time, time, time=time, normal_load=normal_load, metadata={
        "contact_area": 78.54 * M_PER_IN**2, "contact_pressure": 1234.5 * PA_PER_PSI, **metadata})
    refused = []
    for digits in range(1, 13):
        path = tmp_path / f"r{digits}.csv"
        try:
            write_test_record(path, record, digits=digits)
        except ValueError as error:
            assert f"record: written with {digits} significant digits, metadata 'contact_area'" in str(error)
            assert "or pass a larger `digits`" in str(error)
            assert not path.exists()
            refused.append(digits)
            continue
        read = read_test_record(path)
        np.testing.assert_allclose(read.normal_load, record.normal_load, rtol=10.0 ** (1 - digits))
    assert refused and max(refused) < 9


def test_damper_json_with_a_repeated_key_is_refused(tmp_path):
    path = _damper_json(tmp_path)
    path.write_text(path.read_text().replace('"dt":', '"dt": 0.5, "dt":', 1))
    with pytest.raises(ValueError, match=r"line 1, column \d+: the key 'dt' appears a second time at the top"):
        read_friction_damper_json(path)


def test_digitised_loop(tmp_path):
    path = tmp_path / "fig3.csv"
    path.write_text(
        "# source: digitised from Fig. 3 of Constantinou, Mokha & Reinhorn (1990)\n"
        "# protocol: sine amplitude=1 in frequency=0.16 Hz cycles=3 "
        "digitiser=WebPlotDigitizer\n"
        "# normal_load [kip]: 78.5\n"
        "ux [in],fx [kip]\n-1.0,-5.1\n0.0,8.9\n1.0,5.2\n0.0,-8.8\n"
    )
    record = read_test_record(path)
    assert record.is_digitised and record.time is None
    protocol = record.metadata["protocol"]
    assert protocol == Protocol(
        "sine", 1.0 * M_PER_IN, 0.16, 3.0, {"digitiser": "WebPlotDigitizer"}
    )
    assert protocol.duration == pytest.approx(3.0 / 0.16)
    np.testing.assert_allclose(record.normal_load, 78.5 * N_PER_KIP)
    np.testing.assert_allclose(record.ux, np.array([-1.0, 0.0, 1.0, 0.0]) * M_PER_IN)

    out = tmp_path / "fig3_again.csv"
    write_test_record(out, record, units="SI")
    _assert_same(record, read_test_record(out))


def test_protocol_patterns():
    eight = parse_protocol("eight amplitude=4 in frequency=2.77 rad/s")
    assert eight.frequency == pytest.approx(2.77 / (2.0 * np.pi))
    assert eight.cycles is None and eight.duration is None
    t = np.linspace(0.0, 10.0, 501)
    ux, uy = eight.displacement(t)
    np.testing.assert_allclose(ux, 4 * M_PER_IN * np.sin(2.77 * t), atol=1e-15)
    np.testing.assert_allclose(uy, 4 * M_PER_IN * np.sin(2 * 2.77 * t), atol=1e-15)

    triangle = parse_protocol("triangle amplitude=25mm frequency=0.5Hz cycles=2")
    ux, uy = triangle.displacement(np.array([0.0, 0.25, 0.5, 1.0, 1.5, 2.0, 0.125]))
    assert uy is None
    # Zero at t = 0, peak +U0 at a quarter period, -U0 at three quarters, linear between.
    np.testing.assert_allclose(
        ux, [0.0, 0.0125, 0.025, 0.0, -0.025, 0.0, 0.00625], atol=1e-15
    )

    sine = parse_protocol("sine amplitude=0.5 in frequency=0.03 Hz")
    ux, uy = sine.displacement([1.0])
    assert uy is None
    np.testing.assert_allclose(ux, 0.5 * M_PER_IN * np.sin(2 * np.pi * 0.03))
    # The written form reads back to the same protocol.
    assert parse_protocol(triangle.to_text("mm")) == triangle
    again = parse_protocol(eight.to_text())
    assert again.pattern == "eight" and again.amplitude == pytest.approx(4 * M_PER_IN)
    assert again.frequency == pytest.approx(eight.frequency, rel=1e-8)


def test_from_arrays_validation():
    with pytest.raises(ValueError, match="'fx' has 2 samples but 'ux' has 3"):
        records.test_record_from_arrays([0, 1, 2], [0, 1], time=[0, 1, 2])
    with pytest.raises(ValueError, match="'uy' has a non-finite value"):
        records.test_record_from_arrays([0, 1], [0, 1], time=[0, 1], uy=[0, np.nan])
    with pytest.raises(ValueError, match="'time' must increase strictly"):
        records.test_record_from_arrays([0, 1], [0, 1], time=[1, 1])
    with pytest.raises(ValueError, match="protocol"):
        records.test_record_from_arrays([0, 1], [0, 1])
    with pytest.raises(ValueError, match="'direction'"):
        records.test_record_from_arrays(
            [0, 1], [0, 1], time=[0, 1], metadata={"direction": "x"}
        )
    with pytest.raises(ValueError, match="'contact_area' must be a positive number"):
        records.test_record_from_arrays(
            [0, 1], [0, 1], time=[0, 1], metadata={"contact_area": -1.0}
        )
    with pytest.raises(ValueError, match="not a valid key"):
        records.test_record_from_arrays(
            [0, 1], [0, 1], time=[0, 1], metadata={"bad [in] key": "1"}
        )
    with pytest.raises(ValueError, match="no unit in extra_units"):
        records.test_record_from_arrays(
            [0, 1], [0, 1], time=[0, 1], extra_columns={"v": [0, 1]}
        )
    record = records.test_record_from_arrays([0, 1], [0, 1], time=[0, 1], normal_load=5.0)
    np.testing.assert_array_equal(record.normal_load, [5.0, 5.0])
    with pytest.raises(ValueError):
        record.ux[0] = 1.0  # read-only arrays


def test_writer_refuses_time_it_cannot_resolve(tmp_path):
    record = records.test_record_from_arrays([0, 1], [0, 1], time=[1000.0, 1000.0 + 1e-7])
    with pytest.raises(ValueError, match="digits"):
        write_test_record(tmp_path / "t.csv", record, digits=6)
    write_test_record(tmp_path / "t.csv", record, digits=12)
    np.testing.assert_allclose(read_test_record(tmp_path / "t.csv").time, record.time)


def test_comment_lines_are_kept(tmp_path):
    path = tmp_path / "comments.csv"
    path.write_text("# run after re-polishing the plate\n" + _GOOD_HEADER + "0,0,0\n")
    assert read_test_record(path).metadata["comment"] == "run after re-polishing the plate"


# ----------------------------------------------------------------------------------------
# Friction damper JSON (real data, ARTS Laboratory)


def test_damper_json_matches_its_source_notes(external_data):
    record = read_friction_damper_json(external_data / DAMPER_FILE)
    assert len(record) == 7169
    np.testing.assert_allclose(np.diff(record.time), 1.0 / 1024.0, rtol=1e-9)
    assert record.time[-1] - record.time[0] == pytest.approx(7.0)
    assert record.ux.min() / M_PER_IN == pytest.approx(-1.008, abs=1e-3)
    assert record.ux.max() / M_PER_IN == pytest.approx(1.012, abs=1e-3)
    assert record.fx.min() / N_PER_KIP == pytest.approx(-3.52, abs=0.01)
    assert record.fx.max() / N_PER_KIP == pytest.approx(3.61, abs=0.01)
    velocity = record.extra_columns["velocity"] / M_PER_IN  # [in/s]
    sliding_up = np.median(record.fx[velocity > 1.0]) / N_PER_KIP
    sliding_down = np.median(record.fx[velocity < -1.0]) / N_PER_KIP
    assert sliding_up == pytest.approx(2.60, abs=0.02)
    assert sliding_down == pytest.approx(-1.89, abs=0.02)
    energy = np.trapezoid(record.fx, record.ux) / (N_PER_KIP * M_PER_IN)  # [kip in]
    assert energy == pytest.approx(38.0, abs=1.0)
    # The measured velocity agrees with the derivative of the measured displacement.
    derivative = np.gradient(record.ux, record.time) / M_PER_IN
    assert np.median(np.abs(derivative - velocity)) < 0.05 * np.max(np.abs(velocity))
    assert record.normal_load is None and "normal load" in record.metadata["note"]
    assert (
        "Coble" in record.metadata["source"] and "CC BY-SA 4.0" in record.metadata["source"]
    )
    assert record.metadata["protocol"].amplitude == pytest.approx(M_PER_IN)
    assert record.metadata["protocol"].frequency == 1.0
    assert record.extra_units == {
        "velocity": "m/s",
        "actuator_force_1": "N",
        "actuator_force_2": "N",
    }


def _damper_json(tmp_path, **changes):
    content = {
        "data": [[0.0, 0.0, 0.1, 0.0, 10.0, 12.0], [0.5, 0.5, 0.2, 1.0, 11.0, 13.0]],
        "dt": 0.5,
        "sampling freq": 2,
        "displacement units": "in",
        "time units": "s",
        "friction force units": "kip",
        "actuator force units": "lb",
    }
    for key, value in changes.items():
        key = key.replace("_", " ")
        if value is None:
            del content[key]
        else:
            content[key] = value
    path = tmp_path / "2Hz10lbtension0.5amplitude.json"
    path.write_text(json.dumps(content))
    return path


def test_damper_json_small_file(tmp_path):
    record = read_friction_damper_json(_damper_json(tmp_path))
    np.testing.assert_allclose(record.ux, [0.0, 0.5 * M_PER_IN])
    np.testing.assert_allclose(record.fx, [0.1 * N_PER_KIP, 0.2 * N_PER_KIP], rtol=1e-12)
    np.testing.assert_allclose(record.extra_columns["velocity"], [0.0, M_PER_IN])
    np.testing.assert_allclose(
        record.extra_columns["actuator_force_2"],
        [12 * N_PER_LBF, 13 * N_PER_LBF],
        rtol=1e-12,
    )
    assert record.metadata["protocol"].frequency == 2.0
    assert record.metadata["band_tension [lbf]"] == "10"


@pytest.mark.parametrize(
    "changes, expected",
    [
        ({"dt": None}, "'dt' is missing"),
        ({"friction_force_units": None}, "'friction force units' is missing"),
        ({"displacement_units": "kip"}, "'displacement units'"),
        ({"actuator_force_units": "newtonish"}, "'actuator force units'"),
        ({"sampling_freq": 3}, "'sampling freq'"),
        ({"data": [[0.0, 0.0, 0.1, 0.0, 10.0]]}, "row 0"),
        ({"data": [[0.0, 0.0, 0.1, 0.0, 10.0, 1.0], [0.5, None, 0, 0, 0, 0]]}, "row 1"),
        ({"data": [[0.0, 0.0, 0.1, 0.0, 10.0, 1.0], [0.7, 0, 0, 0, 0, 0]]}, "time step"),
    ],
)
def test_damper_json_bad_input(tmp_path, changes, expected):
    path = _damper_json(tmp_path, **changes)
    with pytest.raises(ValueError) as info:
        read_friction_damper_json(path)
    assert expected in str(info.value) and path.name in str(info.value)
