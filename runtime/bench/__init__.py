"""Benchmarks (`make bench`, never timed tests): work-precision against heyoka and the other backends,
maps, design, launches.

No public names: `levitron bench SCENE --kind KIND` runs one (the registry: kinds.py).
"""

__all__: list[str] = []
