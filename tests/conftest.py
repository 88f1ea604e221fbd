import atexit
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

# How XLA compiles the suite's programs. The suite's time is mostly compiling (about 60-90 % of a
# structure test). XLA's CPU compiler with its older fusion emitters compiles the same programs
# in about two thirds of the time of its defaults, and without LLVM's optimisation passes as well
# the fast suite takes 15 min on 2 cores against 22 with the older emitters alone (2026-12-05).
# They compute the same operations; what differs is rounding: without optimisation no multiply
# and add are fused into one rounding, so two programs that differ in form (a load factor of
# exactly 1 multiplied in or left out, one draw run nested or alone) can differ in their last
# bit where the optimised ones agree. Every comparison in the suite is between programs compiled
# alike, or against closed forms, OpenSees and finite differences with their own tolerances; a
# test that asserts such an agreement to the last bit is marked `last_bit` and runs in a process
# of its own with the optimisation passes on (`pytest_pyfunc_call` below). The library, its
# commands and the benchmarks keep XLA's defaults, except the Monte Carlo of a series pendulum on
# a CPU, which compiles with the older emitters (it runs faster with them).
OPTIMISED = os.environ.get("TEFLON_JAX_TEST_COMPILE") == "optimised"
UNOPTIMISED = "--xla_backend_optimization_level=0"
os.environ["XLA_FLAGS"] = " ".join([os.environ.get("XLA_FLAGS", ""), "--xla_cpu_use_fusion_emitters=false",
                                    "" if OPTIMISED else UNOPTIMISED]).strip()

import jax  # noqa: E402  (after XLA_FLAGS: XLA reads them when its CPU client starts)
import pytest  # noqa: E402

jax.config.update("jax_enable_x64", True)

# The commands the tests call keep their compiled programs in $XDG_CACHE_HOME/teflon-jax/jax;
# the tests use a folder of their own, so that a run never reads programs that other runs (other
# versions of the code, other settings) wrote into the user's cache, as a clean machine would not.
os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp(prefix="teflon-jax-tests-")
atexit.register(shutil.rmtree, os.environ["XDG_CACHE_HOME"], ignore_errors=True)

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
                                  dashboard_address=":0", env=env) as local:  # a free port (see _cluster)
        yield local


@pytest.fixture(autouse=True, scope="module")
def _release_compiled_programs():
    """Free each test module's compiled programs when it ends. One process compiles thousands
    of programs over the suite, XLA's CPU code holds memory mappings for each, and a process may
    hold at most vm.max_map_count of them (65,530 by default): past that, a compile aborts."""
    yield
    jax.clear_caches()


@pytest.hookimpl(tryfirst=True)
def pytest_pyfunc_call(pyfuncitem):
    """A test marked `last_bit` asserts that two programs agree to the last bit, which holds
    with LLVM's optimisation passes on: under the suite's compilation without them (top of this
    file) it runs again, alone, in a pytest process of its own with them, and passes or fails
    with that run."""
    if OPTIMISED or pyfuncitem.get_closest_marker("last_bit") is None:
        return None
    env = {**os.environ, "TEFLON_JAX_TEST_COMPILE": "optimised",
           "XLA_FLAGS": " ".join(os.environ["XLA_FLAGS"].replace(UNOPTIMISED, "").split())}
    run = subprocess.run([sys.executable, "-m", "pytest", pyfuncitem.nodeid, "-q", "-p", "no:cacheprovider",
                          "-p", "no:xdist"], cwd=REPO, env=env, capture_output=True, text=True)
    if run.returncode != 0:
        pytest.fail(f"with LLVM's optimisation passes:\n{run.stdout[-6000:]}{run.stderr[-2000:]}", pytrace=False)
    return True
