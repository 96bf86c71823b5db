"""Type stubs of flexmbd (the package; the result classes come from flexmbd._flexmbd)."""

import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._errors import (
    FlexmbdError as FlexmbdError,
    FlexmbdWarning as FlexmbdWarning,
    ModelError as ModelError,
    NumericalError as NumericalError,
    OptionError as OptionError,
    PathStoppedError as PathStoppedError,
    ReadError as ReadError,
    SimulationStoppedError as SimulationStoppedError,
    TooLargeError as TooLargeError,
)
from ._flexmbd import (
    CheckResult as CheckResult,
    ModesResult as ModesResult,
    SimulationResult as SimulationResult,
    StateSpace as StateSpace,
    StaticResult as StaticResult,
    States as States,
)

__version__: str

def load(path: Union[str, "os.PathLike[str]"]) -> Model:
    """Read a model file: ``.toml`` or a SPACAR ``.dat`` file."""

class Model:
    """A model read from TOML or SPACAR text, with the analysis settings of its file."""

    @classmethod
    def from_toml(cls, text: str, file: str = "<string>") -> Model: ...
    @classmethod
    def from_dat(cls, text: str, file: str = "<string>.dat") -> Model: ...
    @property
    def name(self) -> str: ...
    @property
    def file(self) -> str: ...
    @property
    def format(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def node_names(self) -> List[str]: ...
    @property
    def element_names(self) -> List[str]: ...
    @property
    def element_types(self) -> List[str]: ...
    @property
    def n_nodes(self) -> int: ...
    @property
    def n_elements(self) -> int: ...
    @property
    def n_coordinates(self) -> int: ...
    @property
    def coordinate_names(self) -> List[str]: ...
    @property
    def n_deformations(self) -> int: ...
    @property
    def warnings(self) -> List[str]: ...
    def check(
        self,
        *,
        rank_tol: Optional[float] = None,
        auto: bool = False,
        max_suggestions: int = 6,
        method: str = "auto",
    ) -> CheckResult: ...
    def static(
        self,
        *,
        steps: Optional[int] = None,
        compliance: Iterable[str] = (),
        buckling: Optional[int] = None,
        tol_force: Optional[float] = None,
        tol_disp: Optional[float] = None,
        line_search: bool = False,
        path: Optional[str] = None,
    ) -> StaticResult: ...
    def modes(
        self,
        *,
        count: int = 10,
        at_step: Optional[int] = None,
        steps: Optional[int] = None,
        solver: str = "auto",
        path: Optional[str] = None,
    ) -> ModesResult: ...
    def state_space(
        self,
        inputs: Union[str, Sequence[str]],
        outputs: Union[str, Sequence[str]],
        *,
        damping: float = 0.01,
        modes: Optional[int] = None,
        static_correction: bool = False,
        at_step: Optional[int] = None,
        steps: Optional[int] = None,
        solver: str = "auto",
    ) -> StateSpace: ...
    def simulate(
        self,
        *,
        t_end: Optional[float] = None,
        dt: Optional[float] = None,
        fixed_step: bool = False,
        rho_inf: Optional[float] = None,
        tolerance: Optional[Tuple[float, float]] = None,
        output_step: Optional[float] = None,
    ) -> SimulationResult: ...
    def __reduce__(self) -> Tuple[Any, Tuple[str, str, str]]: ...
