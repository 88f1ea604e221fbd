import os
import pathlib

import jax
import pytest

jax.config.update("jax_enable_x64", True)

REPO = pathlib.Path(__file__).resolve().parent.parent


def _external_dir() -> pathlib.Path:
    env = os.environ.get("TEFLON_JAX_EXTERNAL_DATA")
    return pathlib.Path(env) if env else REPO.parent / "shared" / "data" / "external"


@pytest.fixture(scope="session")
def external_data() -> pathlib.Path:
    """The folder of real records (../shared/data/external). Missing: fail in CI, skip elsewhere."""
    path = _external_dir()
    if not path.is_dir():
        message = (
            f"real records not found at {path}; put ../shared beside the clone or set "
            "TEFLON_JAX_EXTERNAL_DATA"
        )
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    return path
