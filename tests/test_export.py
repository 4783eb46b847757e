"""Policy export: TorchScript and ONNX give the same actions as the torch module."""

from __future__ import annotations

import numpy as np
import pytest
import torch

from simlab.rl.exporter import export_policy_as_jit, export_policy_as_onnx
from simlab.rl.rsl_rl import export_policy_as_onnx as rsl_export_onnx

ort = pytest.importorskip("onnxruntime")


def _check_agree(module, folder, obs_dim, normalizer=None):
    jit_file = export_policy_as_jit(module, str(folder), normalizer=normalizer, obs_dim=obs_dim)
    onnx_file = export_policy_as_onnx(module, str(folder), obs_dim, normalizer=normalizer)
    obs = torch.randn(7, obs_dim)
    with torch.no_grad():
        expected = module(normalizer(obs) if normalizer is not None else obs).numpy()
        scripted = torch.jit.load(jit_file)(obs).numpy()
    session = ort.InferenceSession(onnx_file)
    (onnx_out,) = session.run(["actions"], {"obs": obs.numpy()})
    np.testing.assert_allclose(scripted, expected, atol=1e-5)
    np.testing.assert_allclose(onnx_out, expected, atol=1e-5)


def test_mlp_with_normalizer(tmp_path):
    torch.manual_seed(0)
    policy = torch.nn.Sequential(torch.nn.Linear(5, 16), torch.nn.ELU(), torch.nn.Linear(16, 2))
    normalizer = torch.nn.LayerNorm(5)  # any obs -> obs module
    _check_agree(policy, tmp_path, 5, normalizer)


class _CachesItsOutput(torch.nn.Module):
    """As skrl's shared models: the last output kept on the module for the value head."""

    def __init__(self):
        super().__init__()
        self.net = torch.nn.Linear(4, 2)
        self._shared_output = None

    def forward(self, obs):
        self._shared_output = self.net(obs)
        return self._shared_output


def test_a_model_that_caches_its_output_exports_without_a_warning(tmp_path, recwarn):
    torch.manual_seed(0)
    _check_agree(_CachesItsOutput(), tmp_path, 4)  # the export computes the output all the same
    assert not [w for w in recwarn if "assigned during export" in str(w.message)]


def test_rsl_rl_model(tmp_path):
    from rsl_rl.models import MLPModel
    from tensordict import TensorDict

    obs = TensorDict({"policy": torch.randn(3, 6)}, batch_size=[3])
    model = MLPModel(
        obs,
        {"actor": ["policy"]},
        "actor",
        2,
        hidden_dims=[8],
        obs_normalization=True,
        distribution_cfg={"class_name": "GaussianDistribution", "init_std": 1.0},
    )
    model.update_normalization(TensorDict({"policy": torch.randn(50, 6) * 3 + 1}, batch_size=[50]))
    model.eval()
    file = rsl_export_onnx(model, str(tmp_path))
    x = torch.randn(4, 6)
    (onnx_out,) = ort.InferenceSession(file).run(["actions"], {"obs": x.numpy()})
    with torch.no_grad():
        expected = model(TensorDict({"policy": x}, batch_size=[4])).numpy()
    np.testing.assert_allclose(onnx_out, expected, atol=1e-5)


def test_onnx_needs_obs_dim(tmp_path):
    with pytest.raises(ValueError, match="obs_dim"):
        rsl_export_onnx(torch.nn.Linear(2, 2), str(tmp_path))
