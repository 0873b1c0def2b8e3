"""What the scripts under scripts/ record about the machine a result came
from (the benchmarks' JSON and docs name the CPU: machines here differ by up
to 2x)."""

from __future__ import annotations

import os
import platform


def cpu_model() -> str:
    """The CPU's model name and the core count, e.g. "AMD EPYC (2 cores)"."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip() + f" ({os.cpu_count()} cores)"
    except OSError:
        pass
    return f"{platform.processor() or platform.machine()} ({os.cpu_count()} cores)"
