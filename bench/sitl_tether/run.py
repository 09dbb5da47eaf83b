"""Benchmark: the real ArduCopter holding station on the plant's tether against ArduPilot's SIM_Tether model.

Run: ``ARDUPILOT_SITL_BIN=/path/to/arducopter ./tethersim-env python bench/sitl_tether/run.py``

The same mission twice, flown by the real ArduCopter SITL over its JSON interface
(:mod:`uav_bridge.json_physics.flight`): take off in GUIDED from a pad ``--radial`` m from the boat's
guide way and hold ``--altitude`` m above it for ``--hold`` s while the boat heaves
sinusoidally (``--heave`` m amplitude, ``--heave-period`` s: a stand-in for the HPR profiles,
which need the graph). The UAV's tether is

* ``plant``: the plant's quasi-static elastic catenary of the deployed length (fixed here),
  guide way on the heaving boat (:class:`uav_bridge.json_physics.server.PlantTether`);
* ``straight``: ArduPilot's SIM_Tether model, a straight line carrying its whole weight
  mu |d| g along itself, a spring-damper beyond the length
  (:class:`uav_bridge.json_physics.server.StraightTether`).

Both with the thesis's tether (0.042 kg/m) and the same deployed length. Printed per model:
frames, position-hold error about the hold point (horizontal and vertical, RMS and max),
the tether's force on the UAV (mean down and sideways pull, its peak-to-peak over the hold)
and the mean rotor thrust.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np

from tether_dynamics.plant import PlantConfig
from tether_dynamics.plant import TetherPlant
from tether_dynamics.plant import UavConfig
from tether_dynamics.statics.catenary import THESIS_LINEAR_DENSITY
from tether_models.constants import GRAVITY
from uav_bridge.json_physics.flight import FlightError
from uav_bridge.json_physics.flight import HoldPlan
from uav_bridge.json_physics.flight import fly_and_hold
from uav_bridge.json_physics.model import JsonPhysics
from uav_bridge.json_physics.model import JsonPhysicsConfig
from uav_bridge.json_physics.protocol import physics_port
from uav_bridge.json_physics.server import JsonPhysicsServer
from uav_bridge.json_physics.server import PlantTether
from uav_bridge.json_physics.server import StraightTether
from uav_bridge.json_physics.server import heaving_platform
from uav_bridge.mavlink.session import SessionConfig
from uav_bridge.sitl.runner import SitlConfig
from uav_bridge.sitl.runner import SitlError
from uav_bridge.sitl.runner import SitlRunner
from uav_bridge.sitl.runner import locate_binary

FRAME_RATE = 800
GUIDE_WAY = (0.0, 0.0, 0.5)         # m, guide way above the boat origin (the plant's default offset)


def fly(model: str, args, binary: Path, workdir: Path):
    """One flight with the tether ``model``; the hold record and the physics."""
    platform = heaving_platform(args.heave, args.heave_period)
    start = np.array([args.radial, 0.0, 0.0])
    if model == 'plant':
        plant = TetherPlant(PlantConfig(initial_length=args.length, dt=0.01, guide_way_offset=GUIDE_WAY,
                                        uav=UavConfig(mode='prescribed')))
        tether = PlantTether(plant, platform, period=0.01)
    else:
        tether = StraightTether(platform, GUIDE_WAY, THESIS_LINEAR_DENSITY, args.length, GRAVITY, period=0.01)
    physics = JsonPhysics(JsonPhysicsConfig(start=tuple(start), frame_rate=FRAME_RATE))
    sitl = SitlRunner(SitlConfig(binary, binary.parent / 'copter.parm', workdir, instance=args.instance,
                                 speedup=100.0, model='JSON:127.0.0.1',
                                 parameters=(('FRAME_TYPE', 1), ('SIM_RATE_HZ', FRAME_RATE))))
    server = JsonPhysicsServer(physics, physics_port(args.instance), tether=tether, log=lambda line: None)
    config = SessionConfig(url=f'tcp:127.0.0.1:{sitl.config.port}', origin=tuple(start), link_timeout=5.0,
                           reconnect_max=1.0, stream_timeout=5.0, status_period=0.2, arm_timeout=600.0,
                           command_timeout=120.0,
                           stream_rates={'ATTITUDE': 10.0, 'LOCAL_POSITION_NED': 10.0, 'EKF_STATUS_REPORT': 2.0})
    try:
        return fly_and_hold(server, sitl, config, HoldPlan(altitude=args.altitude, hold=args.hold),
                            log=lambda line: None), physics
    finally:
        sitl.stop()
        server.close()


def main() -> int:
    """Fly both models and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--altitude', type=float, default=30.0, help='hold height above the pad, m')
    parser.add_argument('--radial', type=float, default=15.0, help='pad (and hold point) from the guide way, m')
    parser.add_argument('--length', type=float, default=36.0, help='deployed tether length, m')
    parser.add_argument('--hold', type=float, default=60.0, help='hold time, s of sim time')
    parser.add_argument('--heave', type=float, default=1.0, help='boat heave amplitude, m')
    parser.add_argument('--heave-period', type=float, default=8.0, help='boat heave period, s')
    parser.add_argument('--instance', type=int, default=7, help='SITL instance (ports 5760 + 10 N, 9002 + 10 N)')
    parser.add_argument('--models', default='plant,straight', help='tether models to fly: plant, straight')
    args = parser.parse_args()
    try:
        binary = locate_binary('')
    except SitlError as error:
        print(f'skipped: {error}')
        return 0
    print(f'ArduCopter SITL {binary}; hold {args.altitude:g} m up, {args.radial:g} m radial, {args.hold:g} s; '
          f'tether {args.length:g} m of {THESIS_LINEAR_DENSITY} kg/m; boat heave {args.heave:g} m, '
          f'{args.heave_period:g} s')
    header = (f'{"model":<9} {"frames":>7} {"lost":>4} {"climb s":>7} {"hor rms m":>9} {"hor max m":>9} '
              f'{"ver rms m":>9} {"ver max m":>9} {"down N":>7} {"side N":>7} {"|F| p-p N":>9} {"thrust N":>8}')
    rows = []
    for model in args.models.split(','):
        with tempfile.TemporaryDirectory(prefix=f'sitl-tether-{model}-') as workdir:
            try:
                record, physics = fly(model, args, binary, Path(workdir))
            except FlightError as error:
                print(f'{model}: {error}', file=sys.stderr)
                return 1
        error = record.position - record.target
        horizontal = np.linalg.norm(error[:, :2], axis=1)
        magnitude = np.linalg.norm(record.force, axis=1)
        rows.append(f'{model:<9} {len(record.frame_counts):>7d} {record.counts.lost:>4d} {record.climb_time:>7.1f} '
                    f'{np.sqrt(np.mean(horizontal ** 2)):>9.3f} {horizontal.max():>9.3f} '
                    f'{np.sqrt(np.mean(error[:, 2] ** 2)):>9.3f} {np.abs(error[:, 2]).max():>9.3f} '
                    f'{-record.force[:, 2].mean():>7.2f} {np.linalg.norm(record.force[:, :2], axis=1).mean():>7.2f} '
                    f'{np.ptp(magnitude):>9.2f} {record.thrust.mean():>8.2f}')
        print(f'{model}: {record.sim_time:.1f} s of sim time in {record.wall_time:.0f} s wall', flush=True)
    print(header)
    print('\n'.join(rows))
    return 0


if __name__ == '__main__':
    sys.exit(main())
