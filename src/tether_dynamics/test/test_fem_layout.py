"""The compiled kernels' positional model layout (ip, fp, mdl) is named once, and the
builder and the kernels agree on it.
"""

from __future__ import annotations

import ast
import inspect
import re

import numpy as np
import pytest

from tether_dynamics import laws
from tether_dynamics.fem import kernels, scenes
from tether_dynamics.fem.effects import Drag, KelvinVoigt, Wind
from tether_dynamics.fem.model import compile_scene


def _constants(prefix: str) -> dict[str, int]:
    return {name: value for name, value in vars(kernels).items()
            if name.startswith(prefix) and name.isupper() and isinstance(value, int)}


def test_every_field_has_one_constant_at_its_position() -> None:
    assert _constants('IP_') == {f'IP_{n.upper()}': i for i, n in enumerate(kernels.IP_FIELDS)}
    assert _constants('MDL_') == {f'MDL_{n.upper()}': i for i, n in enumerate(kernels.MDL_FIELDS)}
    offsets = np.cumsum([0] + [w for _, w in kernels.FP_FIELDS])
    expected = {f'FP_{n.upper()}': int(o) for (n, _), o in zip(kernels.FP_FIELDS, offsets)}
    expected['FP_SIZE'] = int(offsets[-1])
    assert _constants('FP_') == expected


def test_kernels_index_the_model_only_by_name() -> None:
    source = inspect.getsource(kernels)
    assert re.findall(r'\b(?:ip|fp|mdl)\[\s*\d', source) == []


def _unpacked_names(function: object) -> list[str]:
    tree = ast.parse(inspect.getsource(function).split('\n', 1)[1])
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Name) and node.value.id == 'mdl':
            return [elt.id for elt in node.targets[0].elts]
    raise AssertionError(f'{function} does not unpack mdl')


@pytest.mark.parametrize('stepper', [kernels.run_rk4, kernels.run_verlet])
def test_steppers_unpack_the_tuple_in_the_named_order(stepper: object) -> None:
    assert _unpacked_names(stepper.py_func) == list(kernels.MDL_FIELDS)


def test_right_hand_side_takes_the_tuple_in_the_named_order() -> None:
    params = list(inspect.signature(kernels._rhs.py_func).parameters)
    assert params[:3] == ['t', 'y', 'dy']
    assert params[3:] == list(kernels.MDL_FIELDS)


@pytest.mark.parametrize('element', ['linear', 'quadratic'])
def test_builder_puts_each_value_where_the_kernels_read_it(element: str) -> None:
    scene = scenes.pendulum(element, 4, 'rigid', drag=Drag(0.002, cd_normal=1.1), wind=Wind((3.0, -1.0, 0.5)),
                            damping=KelvinVoigt(7.0))
    model = compile_scene(scene, 0.0, 0.5, 2e-3)
    ip, fp, mdl = model.mdl[kernels.MDL_IP], model.mdl[kernels.MDL_FP], model.mdl
    tet = scene.tether
    assert fp.shape == (kernels.FP_SIZE,)
    assert ip.shape == (len(kernels.IP_FIELDS),)
    assert len(mdl) == len(kernels.MDL_FIELDS)
    assert fp[kernels.FP_EA] == tet.ea
    assert fp[kernels.FP_L0] == tet.l0
    assert fp[kernels.FP_MU] == tet.mu
    assert list(fp[kernels.FP_GRAVITY:kernels.FP_GRAVITY + 3]) == list(scene.gravity)
    assert fp[kernels.FP_END_MASS] == scenes.PENDULUM_MASS
    assert fp[kernels.FP_KV_C] == 7.0
    air = fp[kernels.FP_AIR:kernels.FP_AIR + len(laws.AIR_FIELDS)]
    assert air[laws.AIR_CD_NORMAL] == 1.1
    assert air[laws.AIR_HALF_RHO_D] == 0.5 * Drag(0.002).air_density * 0.002
    assert list(air[laws.AIR_WIND:laws.AIR_WIND + 3]) == [3.0, -1.0, 0.5]
    assert fp[kernels.FP_TABLE_DT] == 2e-3
    assert fp[kernels.FP_STRAIN_LIMIT] == scene.strain_limit
    assert ip[kernels.IP_ELEMENT] == (1 if element == 'linear' else 2)
    assert ip[kernels.IP_N_ELEM] == 4
    assert ip[kernels.IP_N_ALL] == tet.n_nodes
    assert ip[kernels.IP_END_KIND] == 2
    assert (ip[kernels.IP_KV_ON], ip[kernels.IP_DRAG_ON]) == (1, 1)
    assert ip[kernels.IP_N_Q] == model.basis.shape[1]
    assert ip[kernels.IP_FREE_FIRST] == model.free[0]
    assert mdl[kernels.MDL_X].shape == (tet.n_nodes, 3)
    assert mdl[kernels.MDL_Q].shape == (model.basis.shape[1], 3)
    np.testing.assert_allclose(mdl[kernels.MDL_PI_M], scenes.PENDULUM_INERTIA)
    np.testing.assert_array_equal(mdl[kernels.MDL_KIN_IDX], model.kinematic)


def test_packing_refuses_a_missing_or_unknown_field() -> None:
    fields = dict.fromkeys(kernels.IP_FIELDS, 0)
    del fields['n_q']
    with pytest.raises(ValueError, match=r"missing \['n_q'\]"):
        kernels.pack_ip(**fields)
    with pytest.raises(ValueError, match=r"unknown \['reel'\]"):
        kernels.pack_ip(**dict.fromkeys(kernels.IP_FIELDS, 0), reel=1)
    values = {name: np.zeros(width) for name, width in kernels.FP_FIELDS}
    values['gravity'] = np.zeros(2)
    with pytest.raises(ValueError, match='gravity'):
        kernels.pack_fp(**values)
