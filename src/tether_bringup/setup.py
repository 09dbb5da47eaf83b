from glob import glob

from setuptools import find_packages, setup

package_name = 'tether_bringup'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    package_data={package_name: ['py.typed']},
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/scenes', glob('scenes/*.yaml')),
    ],
    install_requires=['setuptools'],
    zip_safe=False,  # py.typed: type checkers read the installed sources (PEP 561)
    maintainer='tethersim',
    maintainer_email='tethersim@example.org',
    description='Bringup of tethersim scenes: sim clock, recorder, replay, bag tools, scenes and reports.',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
    entry_points={
        'console_scripts': [
            'recorder = tether_bringup.recorder_node:main',
            'nodes = tether_bringup.node_group:main',
        ],
        'tethersim.parameters': [
            'recorder = tether_bringup.recorder_params',
        ],
        'tethersim.commands': [
            'run = tether_bringup.cli:RUN',
            'replay = tether_bringup.cli:REPLAY',
            'scenes = tether_bringup.cli:SCENES',
            'bag = tether_bringup.cli:BAG',
            'report = tether_bringup.report_command:REPORT',
        ],
    },
)
