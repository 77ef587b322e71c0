"""The GIL is released while the solver works, so Python threads run."""

import threading
import time

import pbf


def test_step_frames_releases_the_gil(dam_break):
    world = pbf.World.from_scene(dam_break)  # the full scene: ~17,500 particles
    start = time.perf_counter()
    world.step_frame()
    one_frame = time.perf_counter() - start
    worker = threading.Thread(target=world.step_frames, args=(5,))
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    assert world.frame == 6
    # Were the GIL held during a frame, this loop could only tick between
    # frames (a handful of ticks, gaps of a whole frame). Released, it ticks
    # every millisecond or so; the median gap ignores scheduling hiccups on
    # a busy machine.
    gaps = sorted(b - a for a, b in zip(ticks, ticks[1:]))
    assert len(ticks) >= 30, (len(ticks), one_frame)
    assert gaps[len(gaps) // 2] < 0.25 * one_frame, (gaps[len(gaps) // 2], one_frame)


def test_other_threads_wait_for_the_frame(dam_break):
    world = pbf.World.from_scene(dam_break, {"particle_radius": 0.02})
    worker = threading.Thread(target=world.step_frames, args=(5,))
    worker.start()
    seen = []
    while worker.is_alive():
        seen.append((world.frame, world.positions.shape))  # never a half-stepped world
    worker.join()
    assert world.frame == 5 and all(shape == (world.particle_count, 3) for _, shape in seen)
