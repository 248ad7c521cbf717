"""Maps and paths as messages: the simulator's /map read back by the planner node (the grid
the wire carries), nav_msgs/Path both ways, and refused messages."""

from __future__ import annotations

import math

import numpy as np
import pytest
import ros_support  # noqa: F401  (puts the node packages on sys.path)
from builtin_interfaces.msg import Time
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from rclpy.serialization import deserialize_message, serialize_message

from mentor_core.navigation.grid import UNKNOWN, OccupancyGrid
from mentor_core.runtime.guided_planner import wire_grid
from mentor_planner_node import conversions as planner_conv
from mentor_ros_common.messages import occupancy_grid_msg


def _grid(yaw: float = 0.0) -> OccupancyGrid:
    data = np.zeros((3, 4), dtype=np.int8)
    data[0, 3] = 100
    data[2, 0] = UNKNOWN
    data[1, 1] = 42
    return OccupancyGrid(0.05, (-1.5, 2.25, yaw), data)


@pytest.mark.parametrize("yaw", [0.0, 0.7])
def test_the_published_map_reads_back_as_the_wire_grid(yaw: float) -> None:
    grid = _grid(yaw)
    msg = occupancy_grid_msg(grid, Time(sec=3))
    assert msg.header.frame_id == "map" and (msg.info.width, msg.info.height) == (4, 3)
    assert list(msg.data[:4]) == [0, 0, 0, 100]  # row 0 (at the origin) first
    wire = deserialize_message(serialize_message(msg), OccupancyGridMsg)  # as DDS carries it
    back = planner_conv.grid_from_occupancy_grid(wire)
    expected = wire_grid(grid)
    assert back.resolution == expected.resolution != grid.resolution  # float32 on the wire
    np.testing.assert_array_equal(back.data, grid.data)
    assert back.origin[:2] == grid.origin[:2]
    assert back.origin[2] == pytest.approx(yaw, abs=1e-12)


def test_bad_maps_are_refused() -> None:
    msg = occupancy_grid_msg(_grid(), frame_id="odom")  # a scan map's frame
    assert msg.header.frame_id == "odom"
    with pytest.raises(ValueError, match="map frame 'odom'"):
        planner_conv.grid_from_occupancy_grid(msg)
    msg = occupancy_grid_msg(_grid())
    msg.info.width = 5
    with pytest.raises(ValueError, match="12 cells for 5 x 3"):
        planner_conv.grid_from_occupancy_grid(msg)
    msg = occupancy_grid_msg(_grid())
    msg.info.origin.position.x = math.nan
    with pytest.raises(ValueError, match="not finite"):
        planner_conv.grid_from_occupancy_grid(msg)


def test_paths_both_ways() -> None:
    points = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 2.0)])
    msg = planner_conv.path_msg(points, Time(sec=1))
    assert msg.header.frame_id == "map" and len(msg.poses) == 3
    assert msg.poses[1].pose.orientation.z == pytest.approx(math.sin(math.pi / 4))  # faces up
    np.testing.assert_array_equal(planner_conv.path_from_msg(msg), points)
    msg.poses[0].pose.position.y = math.inf
    with pytest.raises(ValueError, match="non-finite"):
        planner_conv.path_from_msg(msg)
    msg = planner_conv.path_msg(points, Time())
    msg.header.frame_id = "base_link"
    with pytest.raises(ValueError, match="path frame"):
        planner_conv.path_from_msg(msg)
    msg.header.frame_id = ""
    msg.poses = []
    with pytest.raises(ValueError, match="no poses"):
        planner_conv.path_from_msg(msg)
