"""Loading, the header-derived cdef, version, constants, devices, defaults."""

import re

import numpy as np
import pytest

import swarmcl


def test_cdef_comes_from_the_installed_header():
    text = swarmcl.header_path.read_text()
    functions = re.findall(r"SWCL_API\s+[\w\s\*]+?\b(swcl_\w+)\s*\(", text)
    assert len(functions) > 30
    for name in functions:
        assert hasattr(swarmcl.lib, name), name


def test_version_matches_header_macros():
    c = swarmcl.constants
    assert swarmcl.__version__ == f"{c['SWCL_VERSION_MAJOR']}.{c['SWCL_VERSION_MINOR']}.{c['SWCL_VERSION_PATCH']}"
    assert swarmcl.lib.swcl_version() == c["SWCL_VERSION_NUMBER"]
    assert swarmcl.NO_AGENT == 0xFFFFFFFF


def test_library_found_inside_package_or_override():
    import os
    if os.environ.get("SWARMCL_LIBRARY"):
        assert swarmcl.library_path.samefile(os.environ["SWARMCL_LIBRARY"])
    else:
        assert swarmcl.library_path.is_file()


def test_devices_listed(ctx):
    devs = swarmcl.devices()
    assert devs, "no OpenCL device"
    assert [d.index for d in devs] == list(range(len(devs)))
    for d in devs:
        assert isinstance(d.type, swarmcl.DeviceType)
        assert d.compute_units > 0 and d.global_memory_bytes > 0
        assert d.device_name and d.platform_name and d.version.startswith("OpenCL")
    assert ctx.device in devs


def test_context_by_index_and_bad_selector():
    d = swarmcl.devices()[0]
    with swarmcl.Context(device=d.index) as c:
        assert c.device == d
    with pytest.raises(swarmcl.SwarmclError) as e:
        swarmcl.Context(device="no-such-device-anywhere")
    assert e.value.status != 0 and str(e.value)


def test_descriptor_defaults_come_from_c():
    c = swarmcl.lib.swcl_noise_desc_default()
    n = swarmcl.NoiseDesc()
    assert n.type == swarmcl.NoiseType(c.type) == swarmcl.NoiseType.CURL
    for name in ("scale", "gain", "time_scale", "boundary_distance", "fd_step"):
        assert np.float32(getattr(n, name)) == np.float32(getattr(c, name)), name
    assert n.seed == c.seed
    assert n.bake_resolution == tuple(c.bake_resolution)
    assert n.boundaries == [] and n.region is None
    m = swarmcl.FieldModel()
    cm = swarmcl.lib.swcl_field_model_desc_default()
    assert m.goal is None and not cm.has_goal
    for name in ("goal_radius", "goal_speed", "goal_falloff", "min_distance"):
        assert np.float32(getattr(m, name)) == np.float32(getattr(cm, name)), name
    assert m.noise == n
    # each instance gets its own list and noise
    assert swarmcl.FieldModel().noise is not m.noise


def test_noise_type_from_string():
    assert swarmcl.NoiseDesc(type="white").type == swarmcl.NoiseType.WHITE
    assert swarmcl.NoiseDesc(type="Gaussian").type == swarmcl.NoiseType.GAUSSIAN
    with pytest.raises(ValueError):
        swarmcl.NoiseDesc(type="pink")


def test_swarm_defaults_come_from_c(ctx):
    d = swarmcl.lib.swcl_swarm_desc_default()
    with swarmcl.Swarm(ctx) as s:
        assert s.agent_count == d.agent_count
    with swarmcl.Swarm(ctx, agent_count=d.capacity + 5) as s:   # capacity grows
        assert s.agent_count == d.capacity + 5


def test_error_classes():
    assert issubclass(swarmcl.InvalidArgumentError, ValueError)
    assert issubclass(swarmcl.OutOfMemoryError, MemoryError)
    for cls in (swarmcl.InvalidArgumentError, swarmcl.InvalidHandleError, swarmcl.NoDeviceError,
                swarmcl.BuildError, swarmcl.OutOfMemoryError, swarmcl.IOError_, swarmcl.ParseError,
                swarmcl.OpenCLError, swarmcl.InternalError):
        assert issubclass(cls, swarmcl.SwarmclError)
