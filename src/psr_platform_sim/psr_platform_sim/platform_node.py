"""ROS 2 node ``platform``: the 3-PSR replicator playing a wave or boat-motion profile.

A thin wrapper around :class:`psr_platform_sim.simulator.PlatformSimulator`: two lockstep
tasks (:mod:`tether_common.lockstep`; every tick runs once, in order, with its own sim
time; the node has no inputs) sample the precomputed motion and publish

* ``/platform/state`` (tether_msgs/PlatformState), ``/platform/reel_pose``
  (geometry_msgs/PoseStamped, frame ``world``) and ``/platform/reel_twist``
  (geometry_msgs/TwistStamped, frame ``world``: the reel mount's velocity and the boat's
  angular velocity, both in world axes) at ``state_rate``,
* ``/platform/imu`` (sensor_msgs/Imu, frame ``boat``, FLU) at ``imu_rate``.

Frames and angles follow REP-103 (see :mod:`psr_platform_sim.simulator`): ``world`` is
ENU with rail 1 on +x; ``boat`` is FLU with x the bow (platform corner 1), y port, z the
platform normal, aligned with ``world`` at the level neutral pose. The reel pose's and the
IMU's orientation are the rotation of ``boat`` in ``world``; the IMU's angular velocity
and specific force are in ``boat``; PlatformState's roll, pitch, yaw (and the commanded
roll, pitch) are the intrinsic Z-Y-X angles of that rotation, not the thesis's
Eq. 2.7-2.9 angles, which only the startup log's tracking error uses.

Profile time is sim time: the profile starts at sim time 0, so the messages and their
stamps do not depend on when the process got to run.
"""

from __future__ import annotations

import sys

from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from rclpy.node import Node
from sensor_msgs.msg import Imu
from tether_msgs.msg import PlatformState

from psr_platform_sim.platform_params import PARAMETERS
from psr_platform_sim.platform_params import from_params
from psr_platform_sim.simulator import PlatformSample
from psr_platform_sim.simulator import PlatformSimulator
from psr_platform_sim.simulator import platform_imu
from tether_common.covariance import diagonal_3x3
from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_models.waves import ProfileError


class PlatformNode(Node):
    """Publishes the replicator's state, reel-mount pose and IMU from a motion profile."""

    def __init__(self, **options) -> None:
        super().__init__('platform', **options)
        try:
            params = declare_parameters(self, PARAMETERS)
            self.sim = PlatformSimulator(from_params(params))
        except (ProfileError, ValueError) as error:
            raise ConfigurationError(str(error)) from None
        self.imu_model = platform_imu(params['seed'], params['imu_gyro_noise'], params['imu_accel_noise'],
                                      params['imu_gyro_bias'], params['imu_accel_bias'], params['imu_rate'])
        self.state_pub = self.create_publisher(PlatformState, '/platform/state', STATE)
        self.pose_pub = self.create_publisher(PoseStamped, '/platform/reel_pose', STATE)
        self.twist_pub = self.create_publisher(TwistStamped, '/platform/reel_twist', STATE)
        self.imu_pub = self.create_publisher(Imu, '/platform/imu', SENSOR)
        # One message object per topic, refilled each tick (publish() serialises it at once),
        # and one sample per tick time for the state and the IMU tasks.
        self.state_msg = PlatformState()
        self.pose_msg = PoseStamped()
        self.twist_msg = TwistStamped()
        for msg in (self.state_msg, self.pose_msg, self.twist_msg):
            msg.header.frame_id = 'world'
        self.imu_msg = Imu()
        self.imu_msg.header.frame_id = 'boat'
        self.imu_msg.orientation_covariance = diagonal_3x3(1e-6)
        self.imu_msg.angular_velocity_covariance = diagonal_3x3(params['imu_gyro_noise'] ** 2)
        self.imu_msg.linear_acceleration_covariance = diagonal_3x3(params['imu_accel_noise'] ** 2)
        self.sampled: tuple[int, PlatformSample] | None = None
        self.lockstep = Lockstep(self)
        self.lockstep.every(1.0 / params['state_rate'], self.state_callback)
        self.lockstep.every(1.0 / params['imu_rate'], self.imu_callback)
        error = self.sim.tracking_error()
        self.get_logger().info(
            f'profile {self.sim.profile_name}: {self.sim.duration:.0f} s, '
            f'{(1.0 - self.sim.inside.mean()) * 100:.1f} % of commands clipped to the workspace, '
            f'{self.sim.limited_ticks} ticks speed/acceleration-limited; RMS tracking error '
            '(Eq. 2.7-2.8 angles) '
            f'heave {error["heave"] * 1000:.1f} mm, roll {error["roll"] * 57.2958:.3f} deg, '
            f'pitch {error["pitch"] * 57.2958:.3f} deg')

    def sample(self, tick: Tick) -> PlatformSample:
        """The simulator's sample at the tick's sim time (taken once per tick time)."""
        if self.sampled is None or self.sampled[0] != tick.time_ns:
            self.sampled = (tick.time_ns, self.sim.sample(tick.seconds))
        return self.sampled[1]

    def state_callback(self, tick: Tick) -> None:
        """Publish /platform/state, /platform/reel_pose and /platform/reel_twist for the tick's sim time."""
        s = self.sample(tick)
        stamp = tick.stamp
        msg = self.state_msg
        msg.header.stamp = stamp
        msg.slider_height = [float(v) for v in s.slider_height]
        msg.slider_velocity = [float(v) for v in s.slider_velocity]
        msg.heave, msg.roll, msg.pitch, msg.yaw = s.heave, s.roll, s.pitch, s.yaw
        msg.surge, msg.sway = s.surge, s.sway
        msg.heave_rate, msg.roll_rate, msg.pitch_rate, msg.yaw_rate = (
            s.heave_rate, s.roll_rate, s.pitch_rate, s.yaw_rate)
        msg.commanded_heave, msg.commanded_roll, msg.commanded_pitch = (
            s.commanded_heave, s.commanded_roll, s.commanded_pitch)
        msg.in_workspace = s.in_workspace
        self.state_pub.publish(msg)
        pose = self.pose_msg
        pose.header.stamp = stamp
        fill_vector(pose.pose.position, s.position)
        fill_quaternion(pose.pose.orientation, s.quaternion)
        self.pose_pub.publish(pose)
        twist = self.twist_msg
        twist.header.stamp = stamp
        fill_vector(twist.twist.linear, s.reel_velocity)
        fill_vector(twist.twist.angular, s.world_angular_velocity)
        self.twist_pub.publish(twist)

    def imu_callback(self, tick: Tick) -> None:
        """Publish /platform/imu: orientation (truth), noisy angular velocity and specific force."""
        s = self.sample(tick)
        gyro, accel = self.imu_model.measure(s.angular_velocity, s.specific_force)
        msg = self.imu_msg
        msg.header.stamp = tick.stamp
        fill_quaternion(msg.orientation, s.quaternion)
        fill_vector(msg.angular_velocity, gyro)
        fill_vector(msg.linear_acceleration, accel)
        self.imu_pub.publish(msg)


def main(args=None):
    """Run the platform node."""
    sys.exit(run_node(PlatformNode, args))


if __name__ == '__main__':
    main()
