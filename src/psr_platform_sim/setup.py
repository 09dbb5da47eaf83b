from setuptools import find_packages, setup

package_name = 'psr_platform_sim'

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
    description='3-PSR wave and boat-motion replicator: kinematics, workspace, design optimization, wave profiles and the platform node.',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
    entry_points={
        'console_scripts': [
            'platform = psr_platform_sim.platform_node:main',
        ],
        'tethersim.parameters': [
            'platform = psr_platform_sim.platform_params',
        ],
        'tethersim.nodes': [
            'platform = psr_platform_sim.platform_node:PlatformNode',
        ],
        'tethersim.commands': [
            'psr = psr_platform_sim.cli:COMMAND',
        ],
    },
)
