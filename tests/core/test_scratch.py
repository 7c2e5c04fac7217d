"""The passes' shared threads (scratch.each): results in order, errors raised, no deadlock."""

import threading
import time

import pytest

from projgrid_addon import scratch


@pytest.fixture(autouse=True)
def workers(monkeypatch):
    monkeypatch.setattr(scratch, "WORKERS", 3)


def test_each_gives_every_result_in_order_using_other_threads():
    threads = set()

    def square(i):
        threads.add(threading.get_ident())
        barrier.wait(timeout=5.0)  # two items at once: they run on two threads
        return i * i

    barrier = threading.Barrier(2)
    assert scratch.each(square, [3, 4]) == [9, 16]
    assert len(threads) == 2


def test_each_raises_the_first_error_once_no_item_runs_and_starts_none_after():
    started, finished = [], []

    def item(i):
        started.append(i)
        time.sleep(0.02)
        if i == 1:
            raise ValueError("item 1")
        finished.append(i)

    with pytest.raises(ValueError, match="item 1"):
        scratch.each(item, range(12))
    at_raise = sorted(started)
    assert sorted(finished + [1]) == at_raise  # none still running
    # those begun with item 1 (one a thread) and at most one more on each other thread
    assert len(at_raise) <= 2 * scratch.WORKERS - 1 < 12
    time.sleep(0.1)
    assert sorted(started) == at_raise  # and none started afterwards


def test_each_inside_each_does_not_wait_on_itself():
    """An item that shares its own work (the pool's threads all busy) finishes: what no
    helper has started, the caller does."""
    result = {}

    def outer(i):
        return sum(scratch.each(lambda j: i * j, range(5)))

    thread = threading.Thread(target=lambda: result.update(v=scratch.each(outer, range(4))),
                              daemon=True)
    thread.start()
    thread.join(timeout=20.0)
    assert not thread.is_alive() and result["v"] == [0, 10, 20, 30]


@pytest.mark.parametrize("rows, columns", [(129, 65), (257, 257), (513, 257), (257, 513),
                                           (3, 40_000), (1, 200_000)])
def test_row_step_makes_chunks_of_at_most_chunk_points_two_or_more_when_large(rows, columns):
    """Chunks of rows of at most CHUNK points (one row at least): one for a viewport grid, an
    even number (whole rows allowing) from SHARED points on."""
    step = scratch.row_step(rows, columns)
    chunks = -(-rows // step)
    assert step * columns <= scratch.CHUNK or step == 1
    if rows * columns < scratch.SHARED:
        assert chunks == 1
    elif rows > 1:
        assert chunks >= 2
    if (rows, columns) in ((257, 257), (513, 257), (257, 513)):
        assert chunks % 2 == 0
