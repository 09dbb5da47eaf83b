from setuptools import find_packages, setup

package_name = 'tether_dynamics'

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
    description='Tether statics (catenary, heave robustness, reference length) and dynamics (finite elements) for tethersim.',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
    entry_points={
        'console_scripts': [
            'plant = tether_dynamics.plant_node:main',
        ],
        'tethersim.parameters': [
            'plant = tether_dynamics.plant_params',
        ],
        'tethersim.nodes': [
            'plant = tether_dynamics.plant_node:PlantNode',
        ],
        'tethersim.commands': [
            'catenary = tether_dynamics.commands.catenary:COMMAND',
            'fem = tether_dynamics.commands.fem:COMMAND',
        ],
    },
)
