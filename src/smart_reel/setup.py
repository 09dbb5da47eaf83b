from setuptools import find_packages, setup

package_name = 'smart_reel'

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
    description='Smart reel: motor and winch, encoder, guide arm, catenary-model and taut controllers, '
                'safety, the reel node and the UAV-surrogate report.',
    license='Apache-2.0',
    extras_require={'test': ['pytest']},
    entry_points={
        'console_scripts': [
            'reel = smart_reel.reel_node:main',
        ],
        'tethersim.parameters': [
            'reel = smart_reel.reel_params',
        ],
        'tethersim.nodes': [
            'reel = smart_reel.reel_node:ReelNode',
        ],
        'tethersim.commands': [
            'reel = smart_reel.cli:COMMAND',
        ],
        'tethersim.reports': [
            'surrogate = smart_reel.surrogate_report:COMMAND',
        ],
    },
)
