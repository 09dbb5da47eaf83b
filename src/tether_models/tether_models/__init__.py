"""The models every simulator shares, without rclpy (issue 36: models below the simulators).

IMU (:mod:`.imu`), RTK dGPS with its faults (:mod:`.dgps`), the reel's stepper vibration
(:mod:`.stepper_vibration`), the sensor suite that samples them (:mod:`.sensor_suite`), the
wave and boat-motion profiles (:mod:`.waves`) and the physical constants (:mod:`.constants`).
A simulator package imports these, never another simulator or the estimator.
"""
