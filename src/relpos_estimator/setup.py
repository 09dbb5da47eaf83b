from setuptools import find_packages, setup

package_name = 'relpos_estimator'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['py.typed']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config', ['config/estimator_tuned.yaml', 'config/estimator_flight.yaml']),
    ],
    install_requires=['setuptools'],
    zip_safe=False,  # py.typed: type checkers read the installed sources (PEP 561)
    maintainer='tethersim',
    maintainer_email='tethersim@example.org',
    description='Simulated RTK dGPS and IMUs with faults, and the relative-altitude Kalman filter with message logic.',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
    entry_points={
        'console_scripts': [
            'sensors = relpos_estimator.sensors_node:main',
            'estimator = relpos_estimator.estimator_node:main',
        ],
        'tethersim.parameters': [
            'sensors = relpos_estimator.sensors_params',
            'estimator = relpos_estimator.estimator_params',
        ],
        'tethersim.nodes': [
            'sensors = relpos_estimator.sensors_node:SensorsNode',
            'estimator = relpos_estimator.estimator_node:EstimatorNode',
        ],
        'tethersim.commands': [
            'estimator = relpos_estimator.cli:COMMAND',
        ],
    },
)
