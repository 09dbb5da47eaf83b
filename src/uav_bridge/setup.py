from setuptools import find_packages, setup

package_name = 'uav_bridge'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['py.typed']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=False,  # py.typed: type checkers read the installed sources (PEP 561)
    maintainer='tethersim',
    maintainer_email='tethersim@example.org',
    description='The UAV end of the graph: MAVLink bridge to ArduPilot (ENU/FLU telemetry, state, commands).',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
    entry_points={
        'console_scripts': [
            'mavlink_bridge = uav_bridge.mavlink_bridge:main',
            'mission = uav_bridge.mission_node:main',
            'sitl = uav_bridge.sitl_node:main',
            'builtin_uav = uav_bridge.builtin_uav_node:main',
            'json_physics = uav_bridge.json_physics_node:main',
        ],
        'tethersim.parameters': [
            'mavlink_bridge = uav_bridge.mavlink_bridge_params',
            'mission = uav_bridge.mission_params',
            'sitl = uav_bridge.sitl_params',
            'builtin_uav = uav_bridge.builtin_uav_params',
            'json_physics = uav_bridge.json_physics_params',
        ],
        'tethersim.nodes': [
            'mission = uav_bridge.mission_node:MissionNode',
            'builtin_uav = uav_bridge.builtin_uav_node:BuiltinUavNode',
        ],
        'tethersim.reports': [
            'mission = uav_bridge.mission_report:COMMAND',
        ],
    },
)
