"""Progress, cancellation and threads: the callback runs on the calling thread, raising in it
cancels the bake, and two bakes from two Python threads at once give the single-bake bits."""
import threading
import time
from typing import Any

import numpy as np
import pytest

import shprt


class Stop(Exception):
    pass


def test_progress_reports_on_the_calling_thread(box):
    calls = []

    def progress(done, total):
        calls.append((done, total, threading.get_ident()))

    shprt.bake(box, bands=2, samples=512, threads=2, progress=progress)
    assert calls, "progress was never called"
    assert {c[2] for c in calls} == {threading.get_ident()}
    assert calls[-1][0] == calls[-1][1] > 0  # the final report: all done
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))


def test_an_error_bounded_bake_reports_one_pass():
    """The shprt program bakes target_error in rounds, each its own stage of the progress whose
    counts start over (BakeRequest::error_rounds); progress(done, total) cannot tell the stages
    apart, so shprt.bake reports one pass: done never falls, total is never 0."""
    scene = shprt.load_scene("builtin:leaky_room")
    calls = []
    shprt.bake(scene, bands=4, target_error=0.01, max_samples=4096, threads=2,
               progress=lambda done, total: calls.append((done, total)))
    assert calls, "progress was never called"
    assert all(total > 0 for _, total in calls)
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:]))
    assert calls[-1][0] == calls[-1][1]


def test_raising_in_progress_cancels_and_reraises(box):
    calls = []

    def progress(done, total):
        calls.append(done)
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        shprt.bake(box, bands=2, samples=512, progress=progress)
    assert len(calls) == 1  # nothing called it again after the bake stopped
    # The library is fine afterwards.
    assert shprt.bake(box, bands=2, samples=64).shape == (box.vertex_count, 4)


def test_a_long_bake_stops_early(box):
    # Enough work that a bake to the end takes many reports; the first one stops it.
    calls = []

    def progress(done, total):
        calls.append((done, total))
        raise Stop()

    room = shprt.load_scene("builtin:room")
    with pytest.raises(Stop):
        shprt.bake(room, bands=2, samples=4096, threads=1, progress=progress)
    done, total = calls[0]
    assert done < total / 2, calls


def test_returning_false_cancels_with_shprt_error(box):
    with pytest.raises(shprt.Error, match="cancelled") as info:
        shprt.bake(box, bands=2, samples=256, progress=lambda done, total: False)
    assert info.value.code == "cancelled"


def test_two_bakes_from_two_threads_at_once(box, sphere):
    jobs: dict[str, tuple[shprt.Mesh, dict[str, Any]]] = {
        "box": (box, dict(bands=4, samples=1024, seed=3, threads=2)),
        "sphere": (sphere, dict(bands=3, samples=2048, sampler="uniform", threads=2)),
    }
    expected = {k: shprt.bake(mesh, **o) for k, (mesh, o) in jobs.items()}
    results, errors = {}, []
    barrier = threading.Barrier(len(jobs))

    def work(name):
        mesh, options = jobs[name]
        try:
            barrier.wait()
            results[name] = shprt.bake(
                mesh, **options,
                progress=lambda d, t: idents.setdefault(name, set()).add(threading.get_ident()))
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    for _ in range(3):
        idents: dict[str, set[int]] = {}
        threads = [threading.Thread(target=work, args=(name,)) for name in jobs]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        assert not errors, errors
        for name in jobs:
            assert results[name].tobytes() == expected[name].tobytes(), name
        # Each bake's callback ran on its own Python thread only.
        assert all(len(s) == 1 for s in idents.values()) and len(set.union(*idents.values())) == 2


def openblas():
    """The OpenBLAS the module uses, through ctypes (None where it cannot be found)."""
    import ctypes
    with open("/proc/self/maps") as maps:
        paths = {line.split()[-1] for line in maps if "openblas" in line and "/" in line}
    for path in sorted(paths):
        lib = ctypes.CDLL(path)
        if hasattr(lib, "openblas_get_num_threads"):
            return lib
    return None


def test_a_bake_ending_does_not_unset_single_threaded_blas_of_another():
    # A bake keeps OpenBLAS single-threaded while it runs (a process-wide setting). Bake X starts
    # first, bake Y starts while X runs, X ends while Y runs: Y must still see one thread, and
    # once both are done the caller's count is back.
    lib = openblas()
    if lib is None:
        pytest.skip("no OpenBLAS in this process")
    saved = lib.openblas_get_num_threads()
    lib.openblas_set_num_threads(2)
    try:
        room = shprt.load_scene("builtin:room")
        x_running, y_running, x_done = threading.Event(), threading.Event(), threading.Event()
        seen_in_y = []

        def x_progress(done, total):
            x_running.set()
            y_running.wait(30)
            return False  # X ends now, inside Y

        def run_x():
            try:
                shprt.bake(room, bands=2, samples=4096, threads=1, progress=x_progress)
            except shprt.Error:
                pass
            x_done.set()

        def y_progress(done, total):
            y_running.set()
            if x_done.is_set():
                seen_in_y.append(lib.openblas_get_num_threads())
                return False  # seen it: stop Y

        x = threading.Thread(target=run_x)
        x.start()
        x_running.wait(30)
        with pytest.raises(shprt.Error, match="cancelled"):
            shprt.bake(room, bands=2, samples=4096, threads=1, progress=y_progress)
        x.join()
        assert seen_in_y == [1]
        assert lib.openblas_get_num_threads() == 2
    finally:
        lib.openblas_set_num_threads(saved)


def test_the_gil_is_released_while_baking():
    # Thread A bakes for a second or more; the main thread sleeps 0.2 s and then needs the GIL
    # again. With the GIL held by the bake it could only go on once the bake is over.
    room = shprt.load_scene("builtin:room")
    started, ends = threading.Event(), {}

    def bake():
        started.set()
        shprt.bake(room, bands=2, samples=4096, threads=1)
        ends["bake"] = time.monotonic()

    a = threading.Thread(target=bake)
    a.start()
    started.wait()
    time.sleep(0.2)
    ends["main"] = time.monotonic()
    a.join()
    assert ends["main"] < ends["bake"], ends


def test_a_progress_return_that_is_no_bool_is_a_type_error(box):
    # Not pybind11's "RuntimeError: Unable to cast Python instance of type <class 'str'>".
    with pytest.raises(TypeError, match="progress: the callback must return True, False or None, "
                                        "not str"):
        shprt.bake(box, bands=2, samples=256, progress=lambda done, total: "yes")  # type: ignore
    with pytest.raises(TypeError, match="not int"):
        shprt.bake(box, bands=2, samples=256, progress=lambda done, total: 1)  # type: ignore


def test_an_exception_in_the_last_progress_call_is_not_lost(box):
    # The final report (done == total) comes when the work is done: the exception still reaches
    # the caller as itself.
    def progress(done, total):
        if done == total:
            raise Stop("at the end")

    with pytest.raises(Stop, match="at the end"):
        shprt.bake(box, bands=2, samples=256, progress=progress)


@pytest.mark.parametrize("transfer", ["unshadowed", "interreflected"])
def test_an_exception_in_progress_propagates_for_every_transfer(box, transfer):
    def progress(done, total):
        raise Stop(transfer)

    with pytest.raises(Stop, match=transfer):
        shprt.bake(box, bands=2, samples=256, transfer=transfer, progress=progress)
