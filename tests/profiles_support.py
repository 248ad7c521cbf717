"""Robot profiles with hand-checkable sensor geometry, for tests that compute ranges by hand."""

from __future__ import annotations

import dataclasses
import math

from mentor_core.sim.robots import RobotProfile, SensorMount, get_profile


def facing_straight_out(profile: RobotProfile) -> RobotProfile:
    """``profile`` with each sensor facing along the outward normal of the body edge it sits on
    (a pair on an edge then looks the same way), so a range is a plain difference of
    coordinates."""

    def normal(x: float, y: float) -> float:
        if math.isclose(abs(x), profile.length / 2):
            return 0.0 if x > 0 else math.pi
        return math.pi / 2 if y > 0 else -math.pi / 2

    mounts = tuple(dataclasses.replace(m, angle=normal(m.x, m.y)) for m in profile.sensors)
    return dataclasses.replace(profile, sensors=mounts)


def single_rays(profile: RobotProfile) -> RobotProfile:
    """``profile`` with every sensor reading one ray straight out (no beams)."""
    return dataclasses.replace(profile, beam_width=0.0, beam_rays=1, beam_sensors=None)


def rays_as_sensors(profile: RobotProfile) -> RobotProfile:
    """``profile`` with every ray of every sensor as a single-ray sensor of its own, in
    ``beam_frames`` order (sensor, then ray): the same mounts and directions, bit for bit."""
    return dataclasses.replace(single_rays(profile), sensors=tuple(
        SensorMount(m.x, m.y, m.angle + a)
        for m, offsets in zip(profile.sensors, profile.ray_offsets, strict=True)
        for a in offsets))


#: the UGV with each pair facing straight out of its edge, one ray each: front pair 0 rad,
#: left pair pi/2, rear pair pi, right pair -pi/2
UGV_STRAIGHT = facing_straight_out(single_rays(get_profile("ugv")))
