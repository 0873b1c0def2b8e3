"""swarmcl: swarm simulation on OpenCL devices, from Python.

A thin layer over the library's C API (``swarmcl/swarmcl.h``), loaded with cffi
in ABI mode; see bindings/python/README.md.

>>> import swarmcl, numpy as np
>>> with swarmcl.Context() as ctx, swarmcl.Swarm(ctx, agent_count=1000, seed=1) as s:
...     s.set_field_model(swarmcl.FieldModel(min_distance=0.03))
...     s.step(10)
...     p = s.read_positions()          # (1000, 3) float32, agent-id order
"""

from ._native import constants, ffi, header_path, lib, library_path
from ._core import NO_AGENT, Context, Recorder, Scenario, Swarm, devices, noise_sample, version
from .descriptors import (Box, DeviceInfo, DeviceType, FieldModel, NoiseDesc, NoiseType, Plane,
                          Sphere, StepStats)
from .energy import (Dataset, EnergyModel, EnergyWeights, Stimulus, StimulusKind, TimeFormat,
                     write_mixed_csv)
from .evaluation import (METRICS, METRIC_UNITS, Metrics, Tracks, distances, entropy_weights, evaluate, plot_pdfs,
                         read_tracks, score, wasserstein)
from .fitting import Parameter, fit, load_ranges
from .spread import fit_spread
from .sweep import load_grid, sweep
from .params import model_parameters
from .synthesis import mix_time_aligned, real_frames
from .force import SHAPES, ForceModel, Keyframe
from .policy import DDPG_POLICY, SHIPPED_POLICY, PolicyModel
from .path import (BoxObstacle, CylinderObstacle, Goal, MeshObstacle, ObjObstacle, PathGroup, PathInfo,
                   PathModel, SphereObstacle)
from .path import Lamp, PathTarget
from .errors import (BuildError, InternalError, InvalidArgumentError, InvalidHandleError, IOError_,
                     NoDeviceError, OpenCLError, OutOfMemoryError, ParseError, SwarmclError)

__version__ = version()

__all__ = [
    "Context", "Swarm", "Scenario", "Recorder", "devices", "noise_sample", "version", "NO_AGENT",
    "NoiseDesc", "NoiseType", "FieldModel", "Sphere", "Box", "Plane", "DeviceInfo", "DeviceType",
    "StepStats",
    "Dataset", "EnergyModel", "EnergyWeights", "Stimulus", "StimulusKind", "TimeFormat", "write_mixed_csv",
    "ForceModel", "Keyframe", "SHAPES", "PolicyModel", "SHIPPED_POLICY", "DDPG_POLICY", "mix_time_aligned", "real_frames",
    "METRICS", "METRIC_UNITS", "Metrics", "distances", "wasserstein", "score", "entropy_weights", "evaluate",
    "plot_pdfs", "Tracks", "read_tracks",
    "fit", "fit_spread", "load_ranges", "Parameter", "model_parameters", "sweep", "load_grid",
    "PathModel", "PathGroup", "PathInfo", "PathTarget", "Lamp", "Goal", "MeshObstacle", "ObjObstacle", "BoxObstacle",
    "SphereObstacle", "CylinderObstacle",
    "SwarmclError", "InvalidArgumentError", "InvalidHandleError", "NoDeviceError", "BuildError",
    "OutOfMemoryError", "IOError_", "ParseError", "OpenCLError", "InternalError",
    "ffi", "lib", "constants", "header_path", "library_path",
]
