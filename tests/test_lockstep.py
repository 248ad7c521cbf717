"""The simulator's command collection: the lockstep barrier and real-time latest commands."""

from __future__ import annotations

import pytest

from mentor_core.runtime.lockstep import HOLD, CommandBarrier, LatestCommands


def test_barrier_steps_when_everyone_has_answered_once() -> None:
    b = CommandBarrier(resend_period=0.1)
    assert b.poll(0.0) == "idle" and not b.complete
    b.ask(["b", "a"], now=10.0)
    assert b.waiting == ("a", "b")
    assert b.answer("a", (0.5, 1.0))
    assert not b.answer("a", (9.0, 9.0))  # a second answer to the same observation: refused
    assert not b.answer("c", (0.1, 0.1))  # nobody asked c
    assert not b.complete and b.poll(10.05) == "wait"
    assert b.poll(10.11) == "resend" and b.poll(10.15) == "wait" and b.poll(10.22) == "resend"
    assert b.answer("b", (-0.5, 2.0))
    assert b.complete and b.poll(10.3) == "idle"
    assert b.take() == {"a": (0.5, 1.0), "b": (-0.5, 2.0)}
    assert not b.complete and not b.answer("a", (0.0, 0.0))  # late answers find nothing


def test_barrier_timeout_holds_the_silent_robots_still() -> None:
    b = CommandBarrier(resend_period=0.1, answer_timeout=1.0)
    b.ask(["a", "b"], now=0.0)
    b.answer("a", (0.2, 0.3))
    assert b.poll(0.95) == "resend"
    assert b.waited(0.95) == pytest.approx(0.95)
    assert b.poll(1.01) == "timeout"
    assert b.complete and b.take() == {"a": (0.2, 0.3), "b": HOLD}
    b.ask(["a"], now=5.0)
    b.clear()
    assert b.poll(100.0) == "idle" and b.waiting == ()
    with pytest.raises(ValueError):
        CommandBarrier(resend_period=0.0)
    with pytest.raises(ValueError):
        CommandBarrier(resend_period=0.1, answer_timeout=-1.0)


def test_latest_commands_in_real_time() -> None:
    latest = LatestCommands()
    latest.answer("a", (0.1, 0.2))
    latest.answer("a", (0.3, 0.4))  # the later one counts
    latest.answer("z", (1.0, 1.0))  # not driving: forgotten at the step
    decisions, missing = latest.take(["a", "b"])
    assert decisions == {"a": (0.3, 0.4), "b": HOLD} and missing == ["b"]
    assert latest.take(["a"]) == ({"a": HOLD}, ["a"])


def test_latest_commands_name_the_robots_without_one() -> None:
    latest = LatestCommands()
    latest.answer("b", (0.1, 0.2))
    assert latest.missing(["c", "b", "a"]) == ["c", "a"]
    assert latest.take(iter(["a", "b"])) == ({"a": HOLD, "b": (0.1, 0.2)}, ["a"])
    assert latest.missing(["b"]) == ["b"]
