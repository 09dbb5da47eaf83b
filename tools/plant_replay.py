"""Replay the tether plant alone on a run's recorded inputs, with other plant parameters.

The plant node steps :class:`TetherPlant` at each tick t on /platform/reel_pose and
/platform/reel_twist and /uav/pose and /uav/twist stamped t, and the /reel/command stamped one
tick earlier (the loop's explicit delay). This tool does the same from a bag, so a run's plant
can be stepped again open loop (the reel and the UAV do not react) with another step, damping
or element count, and its peak tension at the reel compared with the recorded one. With the
scene's parameters it reproduces the recorded /tether/state's tension at the reel exactly.

    ./tethersim-env python tools/plant_replay.py RUN/bag/bag_0.mcap [--dt S] [--damping C] [--elements N]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import yaml
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from tether_dynamics.plant import PlantInputs
from tether_dynamics.plant import TetherPlant
from tether_dynamics.plant_node import plant_config
from tether_dynamics.plant_params import PARAMETERS

TICK_NS = 10_000_000
"""ns, the plant's state period in the outdoor scenes (state_rate 100 Hz)."""
INPUT_TOPICS = ('/platform/reel_pose', '/platform/reel_twist', '/uav/pose', '/uav/twist', '/reel/command')


def _tick(msg) -> int:
    """The message's stamp as a whole number of ticks."""
    return (msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec) // TICK_NS


def _vector(v) -> np.ndarray:
    return np.array([v.x, v.y, v.z])


def _quaternion(q) -> np.ndarray:
    return np.array([q.x, q.y, q.z, q.w])


def read_bag(bag: Path) -> tuple[dict[str, dict[int, object]], dict[int, float]]:
    """The plant's input messages by topic and tick, and the recorded tension at the reel (N) by tick."""
    inputs: dict[str, dict[int, object]] = {topic: {} for topic in INPUT_TOPICS}
    recorded: dict[int, float] = {}
    with bag.open('rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        for _, channel, _, msg in reader.iter_decoded_messages(topics=[*INPUT_TOPICS, '/tether/state']):
            if channel.topic == '/tether/state':
                recorded[_tick(msg)] = msg.tension_reel
            else:
                inputs[channel.topic][_tick(msg)] = msg
    return inputs, recorded


def scene_parameters(bag: Path) -> dict:
    """The plant's parameters of the run (its params/plant.yaml beside bag/) over the declared defaults."""
    params = {spec.name: spec.default for spec in PARAMETERS}
    path = bag.parent.parent / 'params' / 'plant.yaml'
    if path.is_file():
        given = yaml.safe_load(path.read_text(encoding='utf-8'))['/**']['ros__parameters']
        params.update({name: value for name, value in given.items() if name in params})
    return params


def replay(inputs: dict[str, dict[int, object]], params: dict, since: float) -> list[tuple[float, float, int]]:
    """Step the plant over the recorded ticks; (t, tension at the reel N, elements) of every tick from ``since``."""
    plant = TetherPlant(plant_config(params, params['initial_length']))
    command, rows = 0.0, []
    for k in sorted(inputs['/platform/reel_pose']):
        reel_twist, uav, uav_twist = (inputs[topic].get(k) for topic in INPUT_TOPICS[1:4])
        if reel_twist is None or uav is None or uav_twist is None:
            continue
        reel = inputs['/platform/reel_pose'][k]
        latest = inputs['/reel/command'].get(k - 1)
        if latest is not None:
            command = latest.payout_rate
        step_inputs = PlantInputs(
            platform_position=_vector(reel.pose.position), platform_quaternion=_quaternion(reel.pose.orientation),
            platform_velocity=_vector(reel_twist.twist.linear),
            platform_angular_velocity=_vector(reel_twist.twist.angular),
            spool_rate=command / params['spool_radius'], uav_position=_vector(uav.pose.position),
            uav_quaternion=_quaternion(uav.pose.orientation), uav_velocity=_vector(uav_twist.twist.linear),
            uav_angular_velocity=_vector(uav_twist.twist.angular), sea_surface_height=params['sea_level'])
        t = k * TICK_NS / 1e9      # as the node's tick: its stamp in ns over 1e9 (the plant is chaotic in its last bit)
        out = plant.step(t, step_inputs)
        if t >= since:
            rows.append((t, out.tension_reel, out.element_count))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('bag', type=Path, help='a run\'s bag (RUN/bag/bag_0.mcap) with a moving-reel plant driven by '
                                               '/reel/command (reel_drive payout_rate)')
    parser.add_argument('--dt', type=float, help='integration step, s (default: the run\'s)')
    parser.add_argument('--damping', type=float, help='Kelvin-Voigt coefficient, N s (default: the run\'s)')
    parser.add_argument('--elements', type=int, help='element count (default: the run\'s)')
    parser.add_argument('--since', type=float, default=0.0, help='compare peaks from this sim time on, s')
    parser.add_argument('--over', type=float, default=80.0, help='list the ticks whose tension exceeds this, N')
    args = parser.parse_args(argv)
    if not args.bag.is_file():
        print(f'plant_replay: no bag at {args.bag}', file=sys.stderr)
        return 2
    params = scene_parameters(args.bag)
    for name, value in (('integration_step', args.dt), ('damping', args.damping), ('elements', args.elements)):
        if value is not None:
            params[name] = value
    inputs, recorded = read_bag(args.bag)
    rows = replay(inputs, params, args.since)
    t_peak, peak, _ = max(rows, key=lambda row: row[1])
    first = round(args.since * 1e9) // TICK_NS
    recorded_peak = max((value for k, value in recorded.items() if k >= first), default=float('nan'))
    print(f'replayed {params["fidelity"]}, {params["elements"]} elements, dt {params["integration_step"]:g} s, '
          f'damping {params["damping"]:g} N s: peak tension at the reel {peak:.1f} N at {t_peak:.2f} s '
          f'(recorded {recorded_peak:.1f} N)')
    for t, tension, elements in rows:
        if tension > args.over:
            print(f'  {t:.2f} s: {tension:.1f} N, {elements} elements')
    return 0


if __name__ == '__main__':
    sys.exit(main())
