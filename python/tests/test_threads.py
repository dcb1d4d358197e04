"""The GIL is released while the GPU works: another Python thread keeps running during a render."""

import threading
import time

import penumbra


def test_python_threads_run_during_a_render(scene):
    renderer = penumbra.Renderer(scene)
    done = threading.Event()
    span = {}

    def render():
        start = time.perf_counter()
        # A method this renderer has not built: pipelines, the first dispatches, then the frame.
        renderer.render("regular:n=9")
        span["s"] = time.perf_counter() - start
        done.set()

    worker = threading.Thread(target=render)
    ticks = [time.perf_counter()]
    worker.start()
    while not done.is_set():
        time.sleep(0.001)
        ticks.append(time.perf_counter())
    worker.join()
    longest = max(b - a for a, b in zip(ticks, ticks[1:]))
    # Held through the render, the GIL would stop this loop for the whole render.
    assert span["s"] > 0.2, span
    assert longest < span["s"] / 2, (longest, span["s"], len(ticks))
