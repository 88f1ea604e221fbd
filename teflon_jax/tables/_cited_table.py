"""The project's small cited data files (Table 1 and Table 2 of the paper) as CSV with `#` metadata."""

import csv
import pathlib


def data_dir() -> pathlib.Path:
    """Folder holding the tables: `teflon_jax/_data` in a wheel, `<repo>/data` in a checkout."""
    package = pathlib.Path(__file__).resolve().parent.parent
    for candidate in (package / "_data", package.parent / "data"):
        if (candidate / "table1_ptfe_interfaces.csv").is_file():
            return candidate
    raise FileNotFoundError(
        f"teflon-jax data files not found in {package / '_data'} or {package.parent / 'data'}; "
        "reinstall the package (pip install -e .) from a complete checkout."
    )


def read_cited_table(file_name: str) -> tuple[dict[str, str], list[dict[str, str]]]:
    """Read `data/<file_name>`: `# key: value` lines (source, units) and the CSV rows as dicts."""
    meta, lines = {}, []
    with open(data_dir() / file_name, newline="") as handle:
        for line in handle:
            if line.startswith("#"):
                if ":" in line:
                    key, value = line[1:].split(":", 1)
                    meta[key.strip()] = value.strip()
                continue
            lines.append(line)
    return meta, list(csv.DictReader(lines))
