"""warm_up compiles every kernel a plant of the same configuration then runs: a run's first tick
compiles nothing (in a fresh checkout that took about 15 s of the first tick's CPU).
"""

import json
import subprocess
import sys

import pytest

PROBE = r'''
import json, sys
import numpy as np
from numba.core.registry import CPUDispatcher
from tether_dynamics.plant import PlantConfig, PlantInputs, ReelConfig, TetherPlant, UavConfig
from tether_dynamics.plant import bodies, fem_kernels
from tether_dynamics.plant.plant import warm_up

def compiled():
    return {f'{m.__name__}.{name}': len(f.signatures) for m in (bodies, fem_kernels)
            for name, f in vars(m).items() if isinstance(f, CPUDispatcher)}

fidelity, drive = sys.argv[1], sys.argv[2]
config = PlantConfig(fidelity=fidelity, elements=20, dt=1e-4 if fidelity == 'quadratic' else 5e-4,
                     effects=('drag', 'damping') if fidelity != 'quasi_static' else (), damping=20.0,
                     initial_length=33.3, reel=ReelConfig(input=drive, max_length=60.0),
                     uav=UavConfig(mode='prescribed'))
before = compiled()
warm_up(config)
warmed = compiled()
plant = TetherPlant(config)
inputs = PlantInputs(uav_position=np.array([15.0, 0.0, 28.4]))
for k in range(3):
    if drive == 'torque':
        inputs.reel_torque = 0.5
    else:
        inputs.spool_rate = 0.5
    plant.step(0.01 * k, inputs)
print(json.dumps({'before': before, 'warmed': warmed, 'after': compiled()}))
'''


@pytest.mark.parametrize('fidelity', ['quasi_static', 'linear', 'quadratic'])
@pytest.mark.parametrize('drive', ['spool_rate', 'torque'])
def test_a_plant_after_warm_up_compiles_nothing_new(fidelity, drive):
    out = subprocess.run([sys.executable, '-c', PROBE, fidelity, drive], capture_output=True, text=True, check=True)
    counts = json.loads(out.stdout)
    assert counts['warmed'] == counts['after']
    assert sum(counts['warmed'].values()) > sum(counts['before'].values())
