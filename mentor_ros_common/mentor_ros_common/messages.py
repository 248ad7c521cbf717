"""The ROS messages both nodes build from mentor_core's values: a heading's quaternion and an
occupancy grid (the simulator's ``/map``, the planner's scan map). Message building only: no
node, no state."""

from __future__ import annotations

import array

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Pose, Quaternion
from nav_msgs.msg import MapMetaData
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from std_msgs.msg import Header

from mentor_core import MAP_FRAME, OccupancyGrid, yaw_to_quaternion


def quaternion_msg(yaw: float) -> Quaternion:
    """``geometry_msgs/Quaternion`` of a heading (rad) about z."""
    qx, qy, qz, qw = yaw_to_quaternion(yaw)
    return Quaternion(x=qx, y=qy, z=qz, w=qw)


def occupancy_grid_msg(
    grid: OccupancyGrid, stamp: Time | None = None, frame_id: str = MAP_FRAME
) -> OccupancyGridMsg:
    """``nav_msgs/OccupancyGrid`` of a grid in ``frame_id`` (default ``map``): row-major from
    the origin's row (-1 unknown, 0 free .. 100 occupied); the resolution travels as a
    float32 (the inverse of ``mentor_planner_node.conversions.grid_from_occupancy_grid``)."""
    x, y, yaw = grid.origin
    header = Header(stamp=stamp if stamp is not None else Time(), frame_id=frame_id)
    info = MapMetaData(
        map_load_time=header.stamp,
        resolution=float(grid.resolution),
        width=grid.width,
        height=grid.height,
        origin=Pose(position=Point(x=x, y=y, z=0.0), orientation=quaternion_msg(yaw)),
    )
    # an array.array is taken as it is; a list of 4 million cells took 0.3 s to convert
    data = array.array("b", np.ascontiguousarray(grid.data, dtype=np.int8).tobytes())
    return OccupancyGridMsg(header=header, info=info, data=data)


__all__ = ["occupancy_grid_msg", "quaternion_msg"]
