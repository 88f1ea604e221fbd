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


@pytest.fixture(scope="session")
def dask_cluster(tmp_path_factory):
    """One LocalCluster of 2 single-threaded worker processes in float64, shared by the tests of
    the distributed studies (its workers keep a persistent compilation cache folder)."""
    distributed = pytest.importorskip("distributed")
    env = {"JAX_ENABLE_X64": "1", "JAX_PLATFORMS": "cpu",
           "JAX_COMPILATION_CACHE_DIR": str(tmp_path_factory.mktemp("jax-cache")),
           "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS": "0"}
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None, env=env) as local:
        yield local
