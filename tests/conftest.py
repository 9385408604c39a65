"""Shared fixtures: a session-wide headless GL context (moderngl's own test
style) and full-contrast seamless RGBA test tiles. Plain helpers (no fixtures)
are in ``helpers.py``, imported as ``from helpers import ...``."""

import os

import pytest

from helpers import make_test_tile

# --- glibc's allocator keeps the memory it frees ------------------------------------------------
# By default glibc gives freed memory at the top of the heap back to the system, and the next large
# array takes it again page by page, each page zeroed by the kernel: the structural metrics' FFT
# batches (tens of MB, made and freed thousands of times) spent a quarter of their time in the kernel
# (test_metrics_structure.py's flags test: 7.0 s system, 3.1 million page faults; with these, 0.2 s
# and 45 thousand). Set here, before pytest-xdist starts its workers, so that the workers and every
# subprocess the tests start inherit them; other C libraries ignore them. Set in the environment
# already, they are kept. Nothing a test computes changes, only where its memory comes from.
os.environ.setdefault("MALLOC_TRIM_THRESHOLD_", str(1 << 31))
os.environ.setdefault("MALLOC_TOP_PAD_", str(1 << 28))
# numba's OpenMP threads sleep at the end of a parallel loop instead of spinning: two workers with
# two threads each share two cores, and a spinning thread takes the core from the other worker
# (test_render.py: 5 % less CPU time). The same numbers; only how an idle thread waits.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


@pytest.fixture(scope="session")
def _gl_context():
    from spectex._gl import GLUnavailable, create_context

    try:
        ctx = create_context(what="the GL tests")  # the library's one way to make a context
    except GLUnavailable as exc:  # no moderngl, no EGL or no GL 3.3 here: skip the GL tests only
        if os.environ.get("CI"):
            pytest.fail(f"the GL tests never skip in CI: {exc}")
        pytest.skip(str(exc))
    yield ctx
    ctx.release()


@pytest.fixture
def gl(_gl_context):
    """The session's EGL context, made current (moderngl sends calls to the current
    context, and another test may have made its own); the GL error state must be
    clean before and after."""
    _gl_context.__enter__()
    assert _gl_context.error == "GL_NO_ERROR"
    yield _gl_context
    assert _gl_context.error == "GL_NO_ERROR"


@pytest.fixture(scope="session")
def tile():
    return make_test_tile(256, 0)


@pytest.fixture(scope="session")
def tile_maker():
    return make_test_tile


# --- The slowest files first ----------------------------------------------------------------
# ``--dist loadfile`` hands each worker whole files; pytest-xdist orders them by their number of
# tests (function_family's 794 quick ones first), which left the few-but-slow files (the real
# engine clients, the structural metrics, the fits) to the end, where one worker ran them while the
# other had nothing left. Handing out the slowest files first (longest job first) lets both workers
# end together. The order: each file's time in a warm run (2026-11-25, 2-core EPYC, loaded), the
# slowest first; the files not named follow in their usual order. It changes no test, only when
# a file runs.
_SLOWEST_FIRST = (
    "test_engines_real.py", "test_metrics_structure.py", "test_hostile.py", "test_fit.py",
    "test_render_stochastic.py", "test_web_viewer.py", "test_render.py", "test_cli_bake.py",
    "test_texture.py", "test_bake.py", "test_export_engines.py", "test_first_picture.py", "test_snap.py",
    "test_cli_fit.py",
)


def pytest_configure(config):
    if hasattr(config.option, "loadscopereorder"):  # pytest-xdist: keep the order given below
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(config, items):
    rank = {name: i for i, name in enumerate(_SLOWEST_FIRST)}
    order = {id(item): i for i, item in enumerate(items)}
    items.sort(key=lambda item: (rank.get(item.path.name, len(rank)), order[id(item)]))


# --- Spreading the cold compile of the shading kernels over the xdist workers -----------------
# On a clean clone every numba kernel compiles on first use (cache=True keeps it on disk after);
# the kernels of the shading core take 3-25 s each on one core and are used by many test
# files (and by the command-line tests' subprocesses), so two workers, or a worker and a
# subprocess, that reach one of them before it is on disk both compile it. Under xdist (the
# README's ``-n 2``), each worker first goes through the kernels, each under a file lock shared by
# the workers of the run: it compiles those no worker has compiled yet, and takes each other one
# from numba's disk cache once the worker compiling it has finished (waiting for it: at most the
# rest of one kernel's compile). So every kernel is compiled once, the workers share the work as
# it comes, and no test or subprocess starts before all of them are on disk. Tiny inputs, the same
# argument types as every other call: one signature per kernel. Without xdist (a targeted run)
# nothing is warmed: only the kernels the chosen tests use compile. SPECTEX_TEST_WARMUP=0 turns
# it off.


def _warm_jobs():
    import numpy as np

    from spectex.render import Camera, bake
    from spectex.render.cpu import render_cpu
    from spectex.shading.resources import mip_levels, stochastic_tables
    from spectex.shading.sampler import MipTexture, sample
    from spectex.shading.stochastic import sample_stochastic
    from spectex.texture import Layer, SpectralTexture

    tile = np.random.default_rng(0).random((16, 16, 4)).astype(np.float32)
    tex = SpectralTexture(tile, [Layer(size=1.0), Layer(size=4.0, tiling="stochastic", blend="variance")])
    cam = Camera((0.0, 0.0, 2.0), yaw=30.0, pitch=-20.0)
    st = np.linspace(0.0, 1.0, 8)
    d = np.full(8, 0.01)
    # Cold, one core (bench_tests.py, 2026-11-27): render 24.5 CPU s (with shade_ground, which the bake's
    # kernel calls: 8.9 s after it; render and bake are one job, so that no two workers compile
    # shade_ground at once), fast 18.6, stochastic 7.3, sample 2.6. Worker 0 starts with render and
    # bake, worker 1 with fast then sample, and whichever is free first takes stochastic.
    return {
        "render_and_bake_kernels": lambda: (render_cpu(tex, cam, (8, 8)), bake(tex, (4, 4), pixel_size=0.1)),
        "render_kernel_fast": lambda: render_cpu(tex, cam, (8, 8), anisotropy=1.0),
        "stochastic_kernel": lambda: sample_stochastic(stochastic_tables(tex)[0], st, st, dsdx=d, dtdx=d * 0,
                                                       dsdy=d * 0, dtdy=d),
        "sample_kernel": lambda: sample(MipTexture(mip_levels(tex)[0]), st, st, dsdx=d, dtdx=d * 0, dsdy=d * 0,
                                        dtdy=d),
    }


def _warm(jobs: dict, folder, worker: int, workers: int) -> None:
    """Run every job once in this process, each compiled by one worker only (see above)."""
    import fcntl

    own = list(jobs)[worker::workers]  # its share first, then whatever the others have not begun
    waiting = []
    for name in own + [name for name in jobs if name not in own]:
        lock = open(folder / f"warm-{name}.lock", "a")  # closing it lets the lock go
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:  # another worker is compiling it: take the next one meanwhile
            waiting.append((name, lock))
            continue
        with lock:
            jobs[name]()  # compiled here, or loaded from the disk cache where another worker compiled it
    for name, lock in waiting:
        with lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # until the worker compiling it has saved it
            jobs[name]()  # from the disk cache


@pytest.fixture(scope="session", autouse=True)
def _warm_the_shading_kernels(tmp_path_factory):
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    if workers < 2 or os.environ.get("SPECTEX_TEST_WARMUP", "1") == "0":
        return
    worker = int(os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw"))
    shared = tmp_path_factory.getbasetemp().parent  # the run's folder, above each worker's own
    _warm(_warm_jobs(), shared, worker, workers)


# --- Where the cold run's compile time goes ----------------------------------------------------
# SPECTEX_TEST_COMPILE_LOG=FILE appends one line per numba compilation (not a load from numba's
# disk cache) to FILE: worker, seconds, the kernel and its signature, the test that caused it.
# Two workers compiling one kernel show up as two lines; a kernel compiled for several signatures
# as several. Off by default.


def _install_compile_log(path: str) -> None:
    import threading
    import time

    from numba.core import event

    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    local = threading.local()

    class _Log(event.Listener):
        def on_start(self, ev):
            local.depth = getattr(local, "depth", 0) + 1
            if local.depth == 1:
                local.start = time.perf_counter(), time.process_time()

        def on_end(self, ev):
            local.depth -= 1
            if local.depth:
                return  # a function compiled inside another's compilation: counted in the outer one
            wall, cpu = time.perf_counter() - local.start[0], time.process_time() - local.start[1]
            data = ev.data or {}
            func = data["dispatcher"].py_func
            name = f"{func.__module__}.{func.__qualname__}"
            if func.__closure__:  # the noise kernels: one per combination of captured constants
                name += repr(tuple(c.cell_contents for c in func.__closure__
                                   if isinstance(c.cell_contents, (bool, int))))
            test = os.environ.get("PYTEST_CURRENT_TEST", "(outside a test)").rsplit(" ", 1)[0]
            with open(path, "a", encoding="utf-8") as fh:
                fh.write(f"{worker}\t{wall:.2f}\t{cpu:.2f}\t{name}\t{data.get('args')}\t{test}\n")

    event.register("numba:compile", _Log())


if os.environ.get("SPECTEX_TEST_COMPILE_LOG"):
    _install_compile_log(os.environ["SPECTEX_TEST_COMPILE_LOG"])


# --- Where the run's CPU time goes, per test ------------------------------------------------------
# SPECTEX_TEST_CPU_LOG=FILE appends one line per test phase to FILE: worker, CPU seconds of the
# worker, CPU seconds of the subprocesses it waited for, wall seconds, phase, test. A warm-up or a
# module fixture is charged to the test that first needs it. ``benchmarks/bench_tests.py`` reads it.


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    path = os.environ.get("SPECTEX_TEST_CPU_LOG")
    if not path:
        yield
        return
    import resource
    import time

    def now():
        own = resource.getrusage(resource.RUSAGE_SELF)
        kids = resource.getrusage(resource.RUSAGE_CHILDREN)
        return own.ru_utime + own.ru_stime, kids.ru_utime + kids.ru_stime, time.perf_counter()

    before = now()
    yield
    after = now()
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    with open(path, "a", encoding="utf-8") as fh:
        fh.write(f"{worker}\t{after[0] - before[0]:.3f}\t{after[1] - before[1]:.3f}\t{after[2] - before[2]:.3f}"
                 f"\t{item.nodeid}\n")
