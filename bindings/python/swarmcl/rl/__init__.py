"""Deep-RL swarms (issue 15 items 5-6; paper drl-swarm-animation-rule-based-action-generator).

``SwarmVectorEnv`` / ``SwarmWorldEnv`` / ``SwarmSingleEnv`` (Gymnasium,
NumPy only) are imported here, and importing this package registers
``swarmcl/LeaderFollow-v0`` (``ENV_ID``) for ``gymnasium.make`` and
``gymnasium.make_vec``; the DDPG trainer (``swarmcl.rl.ddpg``,
``swarmcl.rl.train``) needs PyTorch, the optional extra ``swarmcl[rl]``,
and is imported on use."""

from .env import ENV_ID, SwarmSingleEnv, SwarmVectorEnv, SwarmWorldEnv, register_envs
from .native_env import SCENARIOS, RlEnv, default_params

register_envs()

__all__ = ["RlEnv", "SwarmVectorEnv", "SwarmWorldEnv", "SwarmSingleEnv", "SCENARIOS", "default_params", "ENV_ID",
           "register_envs"]
