"""The simulated ROSbot of the course as pure models (no runtime import).

Modules: :mod:`~posekit.robot.params` (course parameters), :mod:`~posekit.robot.kinematics`,
:mod:`~posekit.robot.drive` (diff_drive_controller + skid-steer plant),
:mod:`~posekit.robot.encoders`, :mod:`~posekit.robot.imu`, :mod:`~posekit.robot.odometry`
(wheel odometry), :mod:`~posekit.robot.ekf` (robot_localization's role),
:mod:`~posekit.robot.p_controller`, :mod:`~posekit.robot.random_mover`,
:mod:`~posekit.robot.description` (static frames), :mod:`~posekit.robot.lidar`,
:mod:`~posekit.robot.depth` and :mod:`~posekit.robot.contact` (the world as the robot's
sensors and body meet it), and :mod:`~posekit.robot.headless` (a closed loop without the
runtime). The scenes, and their geometry as arrays for ray casting, come from
:mod:`posekit.worlds`. Node wrappers built on posekit.runtime call these models.
"""
