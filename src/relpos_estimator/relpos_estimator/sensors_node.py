"""ROS 2 node ``sensors``: the reel computer's RTK dGPS and the two IMUs, simulated from ground truth.

A thin wrapper around :class:`tether_models.sensor_suite.SensorSuite`. Inputs (truth):

* ``/platform/reel_pose`` (geometry_msgs/PoseStamped, ``world``): the reel's position and
  attitude; its acceleration and angular velocity at tick t come from the poses at t - dt,
  t, t + dt (central differences), so tick t is simulated one tick after its pose arrived;
* ``/platform/state`` (tether_msgs/PlatformState): the slider speeds driving the stepper
  vibration, subscribed only when ``vibration_amplitude`` > 0 (without the vibration the
  speeds are not used);
* ``/truth/relative`` (tether_msgs/RelativePosition) with ``truth: plant``; with
  ``truth: surrogate`` the UAV attachment is fixed in ``world`` at ``surrogate_position``
  (the UAV surrogate of Sec. 5.1) and the relative position is that minus the reel's.

Outputs, all stamped by the truth's stamps, never by arrival:

* ``/imu/reel`` (sensor_msgs/Imu, frame ``boat``) and ``/imu/uav`` (frame ``uav``), sensor-data QoS;
* ``/dgps/fix`` (tether_msgs/DgpsFix, stamp = the modelled arrival time), sensor-data QoS;
* ``/sensors/faults`` (tether_msgs/SensorFault, reliable): each injected fault with its truth;
* ``/truth/relative`` (reliable) with ``truth: surrogate`` only: the truth the sensors used
  so that a run's bag holds what the estimate is scored against.

The node ticks in lockstep (:mod:`tether_common.lockstep`): its inputs are declared with
the producers' period, the node's own (``rate``: the platform's and the plant's state
rate). The central difference needs the pose of t + dt, so tick t simulates the sensors at
t - dt (the platform rests at its first pose before its first tick, k = 1; a node that
joined later starts once it has three poses) from the reel pose
stamped t (no delay) and the platform state and (``truth: plant``) relative position
stamped t - dt (a delay of one period, which also keeps the loop through a reel that
follows the estimate free of a same-tick cycle): every output of tick t is stamped t - dt
or earlier (a consumer declares a delay of one period).
The fixes of a tick are published before its IMU samples.
"""

from __future__ import annotations

import sys

import numpy as np
from builtin_interfaces.msg import Time as TimeMsg
from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from rclpy.qos import HistoryPolicy
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy
from sensor_msgs.msg import Imu
from tether_msgs.msg import DgpsFix
from tether_msgs.msg import PlatformState
from tether_msgs.msg import RelativePosition
from tether_msgs.msg import SensorFault

from relpos_estimator.messages import split_ns
from relpos_estimator.messages import stamp_ns
from relpos_estimator.sensors_params import PARAMETERS
from relpos_estimator.sensors_params import configs
from tether_common.covariance import diagonal_3x3
from tether_common.geometry_fill import fill_quaternion
from tether_common.geometry_fill import fill_vector
from tether_common.lockstep import Input
from tether_common.lockstep import Lockstep
from tether_common.lockstep import Tick
from tether_common.node_main import ConfigurationError
from tether_common.node_main import run_node
from tether_common.qos import SENSOR
from tether_common.qos import STATE
from tether_common.ros_parameters import declare_parameters
from tether_common.rotation import quaternion_rotation
from tether_common.rotation import rotation_vector_between
from tether_models.dgps import FAULT_KINDS
from tether_models.imu import ImuSpec
from tether_models.sensor_suite import ImuSample
from tether_models.sensor_suite import SensorSuite
from tether_models.sensor_suite import SuiteOutput
from tether_models.sensor_suite import Truth

INPUT_DEPTH = 1000
"""Subscription history of the unpaced inputs (fixes) and of test probes: nothing is lost while a consumer lags."""
STILL = np.zeros(3)
"""Slider speeds (m/s) without the stepper vibration."""
STATE_INPUT = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=INPUT_DEPTH, reliability=ReliabilityPolicy.RELIABLE,
                         durability=STATE.durability)


def to_stamp(seconds: float) -> TimeMsg:
    """A builtin_interfaces/Time from seconds (rounded to the nanosecond)."""
    sec, nanosec = split_ns(seconds)
    return TimeMsg(sec=sec, nanosec=nanosec)


class SensorsNode(Node):
    """Publishes simulated IMU, dGPS and fault messages from the platform's and the plant's truth."""

    def __init__(self, **options) -> None:
        super().__init__('sensors', **options)
        try:
            self.params = declare_parameters(self, PARAMETERS)
            suite_config, dgps_config = configs(self.params)
        except ValueError as error:
            raise ConfigurationError(str(error)) from None
        self.suite = SensorSuite(suite_config, dgps_config, self.params['seed'])
        self.period_ns = round(1e9 / self.params['rate'])
        self.dt = self.period_ns * 1e-9
        self.poses: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self.sliders: dict[int, np.ndarray] = {}
        self.relative: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        inputs = [Input('/platform/reel_pose', PoseStamped, self.dt)]
        self.vibrating = self.params['vibration_amplitude'] > 0.0
        if self.vibrating:
            inputs.append(Input('/platform/state', PlatformState, self.dt, self.dt))
        if self.params['truth'] == 'plant':
            inputs.append(Input('/truth/relative', RelativePosition, self.dt, self.dt))
            self.truth_pub = None
        else:
            self.truth_pub = self.create_publisher(RelativePosition, '/truth/relative', STATE)
        self.reel_pub = self.create_publisher(Imu, '/imu/reel', SENSOR)
        self.uav_pub = self.create_publisher(Imu, '/imu/uav', SENSOR)
        self.reel_msg = imu_message('boat', self.suite.reel_imu.spec)
        self.uav_msg = imu_message('uav', self.suite.uav_imu.spec)
        self.fix_pub = self.create_publisher(DgpsFix, '/dgps/fix', SENSOR)
        self.fault_pub = self.create_publisher(SensorFault, '/sensors/faults', STATE)
        self.lockstep = Lockstep(self)
        self.lockstep.every(self.dt, self.on_tick, inputs)

    def on_tick(self, tick: Tick) -> None:
        """Keep tick t's inputs by stamp and simulate the sensors at t - dt once its truth is complete."""
        pose = tick.inputs['/platform/reel_pose']
        if pose is not None:
            p, q = pose.pose.position, pose.pose.orientation
            self.poses[stamp_ns(pose.header.stamp)] = (np.array([p.x, p.y, p.z]), np.array([q.x, q.y, q.z, q.w]))
        state = tick.inputs.get('/platform/state')
        if state is not None:
            self.sliders[stamp_ns(state.header.stamp)] = np.array(state.slider_velocity, dtype=float)
        relative = tick.inputs.get('/truth/relative')
        if relative is not None:
            p, a = relative.position, relative.acceleration
            self.relative[stamp_ns(relative.header.stamp)] = (np.array([p.x, p.y, p.z]), np.array([a.x, a.y, a.z]))
        t_ns = tick.time_ns - self.period_ns
        truth = self.truth(t_ns)
        if truth is not None:
            self.publish_truth(t_ns, truth)
            self.publish(self.suite.step(t_ns * 1e-9, truth))
        self.forget(t_ns - self.period_ns)

    def truth(self, t_ns: int) -> Truth | None:
        """Ground truth at ``t_ns`` from the buffered inputs, or None if one is missing."""
        d = self.period_ns
        poses = [self.poses.get(t_ns + k * d) for k in (-1, 0, 1)]
        if poses[0] is None and t_ns == d:
            poses[0] = poses[1]  # before its first tick the platform rests at its first pose (profile ramp)
        slider = self.sliders.get(t_ns) if self.vibrating else STILL
        if any(p is None for p in poses) or slider is None:
            return None
        known = [p for p in poses if p is not None]
        positions = [p for p, _ in known]
        quaternions = [q for _, q in known]
        acceleration = (positions[2] - 2.0 * positions[1] + positions[0]) / self.dt**2
        angular_velocity = rotation_vector_between(quaternions[0], quaternions[2]) / (2.0 * self.dt)
        if self.params['truth'] == 'plant':
            relative = self.relative.get(t_ns)
            if relative is None:
                return None
            rel_position, rel_acceleration = relative
            rel_velocity = np.zeros(3)
        else:
            rel_position = np.asarray(self.params['surrogate_position']) - positions[1]
            rel_velocity = -(positions[2] - positions[0]) / (2.0 * self.dt)
            rel_acceleration = -acceleration
        reel_rotation = quaternion_rotation(quaternions[1], '/platform/reel_pose').matrix
        return Truth(reel_rotation, angular_velocity, acceleration, rel_position, rel_acceleration,
                     slider, rel_velocity)

    def forget(self, before_ns: int) -> None:
        """Drop buffered inputs older than ``before_ns``."""
        for buffer in (self.poses, self.sliders, self.relative):
            for key in [key for key in buffer if key < before_ns]:
                del buffer[key]

    def publish_truth(self, t_ns: int, truth: Truth) -> None:
        """With ``truth: surrogate``, publish the relative position the sensors used on /truth/relative."""
        if self.truth_pub is None:
            return
        msg = RelativePosition()
        msg.header.stamp = to_stamp(t_ns * 1e-9)
        msg.header.frame_id = 'world'
        fill_vector(msg.position, truth.relative_position)
        fill_vector(msg.velocity, truth.relative_velocity)
        fill_vector(msg.acceleration, truth.relative_acceleration)
        self.truth_pub.publish(msg)

    def publish(self, out: SuiteOutput) -> None:
        """Publish one tick's arrived fixes, faults and IMU samples (the fixes first)."""
        for fix in out.fixes:
            msg = DgpsFix()
            msg.header.stamp = to_stamp(fix.arrival)
            msg.header.frame_id = 'world'
            msg.fix_time = to_stamp(fix.fix_time)
            fill_vector(msg.relative_position, fix.position)
            fill_vector(msg.position_std, fix.std)
            msg.status = fix.status
            msg.sequence = fix.sequence
            self.fix_pub.publish(msg)
        for sensor, fault in out.faults:
            msg = SensorFault()
            msg.header.stamp = to_stamp(fault.time)
            msg.header.frame_id = 'world'
            msg.sensor = sensor
            msg.kind = FAULT_KINDS.index(fault.kind)
            msg.kind_name = fault.kind
            msg.fix_time = to_stamp(fault.fix_time)
            msg.sequence = fault.sequence
            fill_vector(msg.truth, fault.truth)
            fill_vector(msg.reported, fault.reported)
            self.fault_pub.publish(msg)
        self.reel_pub.publish(fill_imu(self.reel_msg, out.reel))
        self.uav_pub.publish(fill_imu(self.uav_msg, out.uav))


def imu_message(frame: str, spec: ImuSpec) -> Imu:
    """sensor_msgs/Imu of ``frame`` with the class's white-noise variances on the covariance diagonals,
    refilled by :func:`fill_imu` each tick (publish() serialises it at once).
    """
    msg = Imu()
    msg.header.frame_id = frame
    msg.angular_velocity_covariance = diagonal_3x3(spec.gyro_noise**2)
    msg.linear_acceleration_covariance = diagonal_3x3(spec.accel_noise**2)
    return msg


def fill_imu(msg: Imu, sample: ImuSample) -> Imu:
    """``msg`` with the sample's stamp, orientation, angular velocity and specific force."""
    msg.header.stamp = to_stamp(sample.t)
    fill_quaternion(msg.orientation, sample.quaternion)
    fill_vector(msg.angular_velocity, sample.gyro)
    fill_vector(msg.linear_acceleration, sample.accel)
    return msg


def main(args=None):
    """Run the sensors node."""
    sys.exit(run_node(SensorsNode, args))


if __name__ == '__main__':
    main()
