"""Progress bars for long builds (a cone map of a large map, a distance volume): the core
reports each build's rows as it goes (`_core.set_progress_hook`); a build still running after
`SHOW_AFTER` seconds gets a tqdm bar when a terminal or a notebook is attached (tqdm is in the
bench and notebooks extras; without it, nothing is shown). Builds that took over a second are
kept in `pomkit._cache.cache_dir()` by the core (`_core.set_cache_dir`), keyed by content.
"""

from __future__ import annotations

import sys
import time
from typing import Any

from . import _core

SHOW_AFTER = 2.0

# label -> (start time, bar or None)
_builds: dict[str, list[Any]] = {}


def _attached() -> bool:
    """A terminal or a notebook is there to show a bar."""
    if "ipykernel" in sys.modules:
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _bar(label: str, total: int, done: int):
    if not _attached():
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    return tqdm(total=total, initial=done, desc=f"pomkit: building the {label}", unit="rows", leave=False)


def report(label: str, done: int, total: int) -> None:
    """The core's hook: `done` of `total` rows of the build `label`."""
    now = time.monotonic()
    st = _builds.get(label)
    if st is None or done == 0:
        st = _builds[label] = [now, None]
    start, bar = st
    if bar is None and done < total and now - start > SHOW_AFTER:
        bar = st[1] = _bar(label, total, done)
    elif bar is not None:
        bar.update(done - bar.n)
    if done >= total:
        if bar is not None:
            bar.close()
        _builds.pop(label, None)


def install() -> None:
    """Set the hook and the cache directory in the core (the Renderer does, each time one is
    made, so that POMKIT_CACHE is read then)."""
    from ._cache import cache_dir
    _core.set_progress_hook(report)
    _core.set_cache_dir(str(cache_dir()))
