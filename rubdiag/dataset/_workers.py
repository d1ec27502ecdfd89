"""What a worker shares with this process, so that its rows have this process's bits.

A row is a function of its run and of what computes it: rubdiag's sources, the numpy, scipy,
Numba and llvmlite versions, and the BLAS libraries with their kernels (the simulator's inputs
come from LAPACK, and a rubbing run is chaotic: one last bit of an input changes its contact
episodes after a second; ``rubdiag/_blas.py``). BLAS and OpenMP run on one thread in every
worker: a threaded product sums in another order.

Local workers are forked from this process and inherit all of it; they also set the thread
variables, so that a library loaded after their start (which ``threadpool_limits`` does not
reach) starts on one thread too, as in a Dask worker, whose nanny sets the same variables.
A local worker pins OpenBLAS's kernels as it starts (:func:`rubdiag.pin_blas_kernels`): a
worker started afresh (not forked) loads the kernels this process named in the environment.

Dask workers are processes of their own, and ``distributed`` loads numpy (and OpenBLAS) before
a task can run, so no call in a task can pin their kernels: a worker follows
``OPENBLAS_CORETYPE`` as its nanny passed it at the start. A ``LocalCluster`` made in this
process inherits it; workers started by ``dask worker`` elsewhere pick the kernels of their
CPU (SkylakeX on AVX-512 machines), and all their rows differ. :func:`align_dask_workers`
compares every worker's :func:`signature` with this process's before a run is sent; where
only the kernels differ it restarts the workers with this process's kernels in their
environment at the start (:func:`pin_kernels_plugin`), and anything that still differs is a
``ValueError`` naming the worker and the difference.
"""

from __future__ import annotations

import os
from importlib import metadata

__all__ = ["THREAD_ENVIRON", "align_dask_workers", "differences", "pin_kernels_plugin",
           "signature", "start_local_worker"]

#: one thread for every BLAS and OpenMP library a worker loads (Dask's nanny default)
THREAD_ENVIRON = {"OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
_KERNELS = "OPENBLAS_CORETYPE"
_VERSIONS = ("numpy", "scipy", "numba", "llvmlite")


def start_local_worker() -> None:
    """Initialise a local worker process: this process's BLAS kernels (pinned before the
    worker loads numpy, where it has not yet), one thread for the BLAS and OpenMP libraries it
    has (numpy's and scipy.linalg's BLAS loaded first) and for those it loads later."""
    from rubdiag._blas import _pin

    _pin()                      # first: before anything below loads numpy
    from threadpoolctl import threadpool_limits

    from rubdiag._blas import blas_signature

    os.environ.update(THREAD_ENVIRON)
    blas_signature()            # loads scipy.linalg's BLAS, so that the limit reaches it
    threadpool_limits(limits=1)
    _end_with_parent()


def _end_with_parent(period_s: float = 1.0) -> None:
    """End this worker once the process that started it is gone (killed, SIGKILL too): a
    pool's worker would otherwise wait on its queues for ever, holding its memory."""
    import threading
    import time

    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(period_s)
        os._exit(1)             # no clean-up to do: the job's rows are the parent's to store

    threading.Thread(target=watch, name="rubdiag-parent-watch", daemon=True).start()


def signature() -> dict:
    """What decides a row's bits besides its run, in this process: ``{"rubdiag": digest of
    the package's sources as they are now, "numpy": version, … "blas": [[library, version,
    kernels], …]}``."""
    from rubdiag._blas import blas_signature
    from rubdiag._cache import sources_digest

    return {"rubdiag": sources_digest(("**/*.py",))[:16],
            **{name: metadata.version(name) for name in _VERSIONS}, "blas": blas_signature()}


def differences(here: dict, there: dict) -> list[str]:
    """What differs between two :func:`signature`\\ s, worded for a message (empty: none)."""
    return [f"{name} {there.get(name)!r} (this process: {here.get(name)!r})"
            for name in sorted(set(here) | set(there)) if here.get(name) != there.get(name)]


def _kernels(blas: list) -> str | None:
    """The one kernel set of a BLAS signature's OpenBLAS libraries, or None."""
    names = {kernels for api, _version, kernels in blas if api == "openblas"}
    return names.pop() if len(names) == 1 else None


def pin_kernels_plugin(kernels: str):
    """A Dask nanny plugin: the nanny's worker starts again with ``OPENBLAS_CORETYPE=kernels``
    and one BLAS thread in its environment, before it first imports numpy."""
    from distributed.diagnostics.plugin import NannyPlugin

    environ = {_KERNELS: kernels, **THREAD_ENVIRON}

    class PinKernels(NannyPlugin):      # defined here: distributed is an optional dependency
        name = "rubdiag-pin-kernels"
        restart = True                  # the nanny restarts its worker once set up

        async def setup(self, nanny) -> None:
            # a nanny puts ``pre_spawn_env`` into its own environment before it starts a
            # worker, ``env`` only once the worker has imported numpy: the kernels need the first
            nanny.pre_spawn_env.update(environ)
            nanny.env.update(environ)

    return PinKernels()


def align_dask_workers(client) -> None:
    """Make every worker of ``client`` run what this process runs (module docstring), or
    raise a ValueError naming the worker and what differs."""
    here = signature()
    kernels = _kernels(here["blas"])
    mismatched = _mismatched(client, here)
    if mismatched and kernels is not None and all(
            _without_blas(there) == _without_blas(here) for there in mismatched.values()):
        n_workers = len(client.scheduler_info()["workers"])
        client.register_plugin(pin_kernels_plugin(kernels))
        client.wait_for_workers(n_workers, timeout=120)
        mismatched = _mismatched(client, here)
    if mismatched:
        worker, there = sorted(mismatched.items())[0]
        how = ("the same installation" if kernels is None else
               f"the same installation and {_KERNELS}={kernels} in their environment (e.g. "
               f"{_KERNELS}={kernels} dask worker ADDRESS)")
        raise ValueError(f"the Dask worker {worker} would not give this process's rows: it "
                         f"runs {'; '.join(differences(here, there))}. Start the workers "
                         f"with {how}, or run locally (--jobs)")


def _without_blas(sig: dict) -> dict:
    return {name: value for name, value in sig.items() if name != "blas"}


def _mismatched(client, here: dict) -> dict[str, dict]:
    return {worker: there for worker, there in client.run(signature).items() if there != here}
