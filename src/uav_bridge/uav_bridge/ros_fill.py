"""The UAV's ``/uav/pose`` and ``/uav/twist`` from arrays (shared by the UAV nodes)."""

from __future__ import annotations

from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped

from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector


def pose_and_twist(stamp, position, quaternion, velocity, angular_velocity) -> tuple[PoseStamped, TwistStamped]:
    """The UAV's ``/uav/pose`` and ``/uav/twist`` in ``world`` (ENU; angular velocity expressed in world)."""
    pose, twist = PoseStamped(), TwistStamped()
    fill_pose_and_twist(pose, twist, stamp, position, quaternion, velocity, angular_velocity)
    return pose, twist


def fill_pose_and_twist(pose: PoseStamped, twist: TwistStamped, stamp, position, quaternion, velocity,
                        angular_velocity) -> None:
    """Set every field of ``pose`` and ``twist`` as :func:`pose_and_twist` makes them (a node that publishes
    every tick refills one pair of messages).
    """
    pose.header.stamp, pose.header.frame_id = stamp, 'world'
    fill_vector(pose.pose.position, position)
    fill_quaternion(pose.pose.orientation, quaternion)
    twist.header.stamp, twist.header.frame_id = stamp, 'world'
    fill_vector(twist.twist.linear, velocity)
    fill_vector(twist.twist.angular, angular_velocity)
