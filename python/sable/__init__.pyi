"""Type hints of the sable package (python/sable/__init__.py)."""
import os
from typing import Any, Sequence

from ._sable import (InputError as InputError, IoError as IoError, Scenario as Scenario,
                     Simulation as Simulation, SimulationError as SimulationError,
                     __version__ as __version__, load_snapshot as load_snapshot)

def analyze(source: str | os.PathLike[str] | Sequence[str | os.PathLike[str]] | Simulation,
            out_dir: str | os.PathLike[str] | None = None, **options: Any) -> dict[str, Any]: ...
