from setuptools import find_packages, setup

package_name = 'tether_models'

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
    description='The models every simulator shares, without rclpy: IMU, RTK dGPS and stepper vibration, '
                'the sensor suite, wave and boat-motion profiles, physical constants.',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
)
