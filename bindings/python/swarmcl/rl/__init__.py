"""Deep-RL swarms (issue 15 items 5-6; paper drl-swarm-animation-rule-based-action-generator).

``SwarmVectorEnv`` / ``SwarmSingleEnv`` (Gymnasium, NumPy only) are imported
here; the DDPG trainer (``swarmcl.rl.ddpg``, ``swarmcl.rl.train``) needs
PyTorch, the optional extra ``swarmcl[rl]``, and is imported on use."""

from .env import SwarmSingleEnv, SwarmVectorEnv
from .native_env import SCENARIOS, RlEnv, default_params

__all__ = ["RlEnv", "SwarmVectorEnv", "SwarmSingleEnv", "SCENARIOS", "default_params"]
