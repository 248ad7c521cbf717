"""Shared pytest setup.

ROS 2 isolation: DDS discovery must never leave the loopback, and parallel test workers must
never see each other's nodes. This is set here, at import time, before any test module can
call ``rclpy.init``: ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`` and a ``ROS_DOMAIN_ID`` of
60 + the pytest-xdist worker number (60 without xdist; ``MENTOR_TEST_ROS_DOMAIN_BASE`` moves
the base, so that two checkouts can run their ROS tests at once). Subprocesses started by tests
inherit both; :func:`ros_env` gives a copy of that environment for them.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from typing import Any

import pytest

ROS_DOMAIN_BASE = int(os.environ.get("MENTOR_TEST_ROS_DOMAIN_BASE", "60"))


def _worker_number() -> int:
    match = re.fullmatch(r"gw(\d+)", os.environ.get("PYTEST_XDIST_WORKER", ""))
    return int(match.group(1)) if match else 0


ROS_DOMAIN_ID = ROS_DOMAIN_BASE + _worker_number()
os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
os.environ["ROS_DOMAIN_ID"] = str(ROS_DOMAIN_ID)
os.environ.pop("ROS_STATIC_PEERS", None)
# the tests are about the shipped robot file, whatever file a developer's shell names
os.environ.pop("MENTOR_ROBOTS", None)


@pytest.fixture
def ros_env() -> dict[str, str]:
    """A copy of the test environment with localhost-only discovery and this worker's domain."""
    env = dict(os.environ)
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env["ROS_DOMAIN_ID"] = str(ROS_DOMAIN_ID)
    return env


@pytest.fixture
def graph() -> Iterator[Any]:
    """A ``ros_support.Graph`` (rclpy context + executor on sim time), closed after the test."""
    from ros_support import Graph  # rclpy only for the tests that ask for a graph

    g = Graph()
    try:
        yield g
    finally:
        g.close()
