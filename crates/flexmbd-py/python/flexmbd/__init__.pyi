"""Type stubs of flexmbd (the package; the result classes come from flexmbd._flexmbd)."""

import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

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

def load(
    path: Union[str, "os.PathLike[str]"],
    set: Optional[Union[Mapping[str, float], Iterable[Tuple[str, float]]]] = None,
) -> Model:
    """Read a model file: ``.toml`` or a SPACAR ``.dat`` file."""

Vec3 = Union[Sequence[float], npt.ArrayLike]

class Model:
    """A model: its document (as a TOML model file states it) and the analyses on it.
    Build or edit it by names; it is compiled when an analysis next asks."""

    def __init__(self, name: str = "model", *, file: str = "<python>") -> None:
        """An empty model named ``name``."""

    @classmethod
    def from_toml(
        cls,
        text: str,
        file: str = "<string>",
        set: Optional[Union[Mapping[str, float], Iterable[Tuple[str, float]]]] = None,
    ) -> Model: ...
    @classmethod
    def from_dat(cls, text: str, file: str = "<string>.dat") -> Model: ...
    @property
    def name(self) -> str: ...
    @property
    def file(self) -> str: ...
    @property
    def format(self) -> str: ...
    @property
    def source(self) -> Optional[str]: ...
    @property
    def parameters(self) -> Dict[str, float]: ...
    def copy(self) -> Model: ...
    def to_toml(self) -> str: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def get(self, path: str) -> Any:
        """The value at ``path`` (``"sections.sheet.t"``, ``"nodes.c.x"``, ``"static.steps"``)."""
    def set(self, path: str, value: Any) -> None:
        """Set the value at ``path``: ``model.set("sections.sheet.t", 0.2e-3)``."""
    def add_node(
        self, name: str, xyz: Vec3 = ..., rot: bool = False, *, at: Optional[str] = None, replace: bool = False
    ) -> None: ...
    def add_truss(
        self, name: str, nodes: Sequence[str], ea: float, *, free: Iterable[int] = (), input: Iterable[int] = (), damping: Optional[float] = None, replace: bool = False
    ) -> None: ...
    def add_beam(
        self,
        name: str,
        nodes: Sequence[str],
        *,
        section: Optional[str] = None,
        material: Optional[str] = None,
        orient: Optional[Vec3] = None,
        segments: Optional[int] = None,
        ct: Optional[float] = None,
        ea: Optional[float] = None,
        gj: Optional[float] = None,
        eiy: Optional[float] = None,
        eiz: Optional[float] = None,
        rho_a: Optional[float] = None,
        free: Iterable[int] = (),
        input: Iterable[int] = (),
        fixed: Iterable[int] = (),
        damping: Optional[float] = None,
        replace: bool = False,
    ) -> None: ...
    def add_hinge(
        self, name: str, nodes: Sequence[str], axis: Vec3, k: float = 0.0, *, free: Iterable[int] = (), input: Iterable[int] = (), damping: Optional[float] = None, replace: bool = False
    ) -> None: ...
    def add_rigid(self, name: str, nodes: Sequence[str], *, replace: bool = False) -> None: ...
    def input_deformation(self, element: str, modes: Iterable[int]) -> None: ...
    def add_material(
        self, name: str, *, E: float, nu: Optional[float] = None, G: Optional[float] = None, rho: float = 0.0, damping: Optional[float] = None, replace: bool = False
    ) -> None: ...
    def add_section(
        self, name: str, shape: str = "rectangle", *, shear: bool = True, replace: bool = False, **dims: float
    ) -> None: ...
    def fix(self, node: str, dofs: Union[None, str, Sequence[str]] = None) -> None: ...
    def add_input(self, node: str, dofs: Union[None, str, Sequence[str]] = None) -> None: ...
    def add_load(self, node: str, force: Vec3 = ..., moment: Vec3 = ...) -> None: ...
    def add_mass(self, node: str, m: float) -> None: ...
    def add_inertia(self, node: str, I: Sequence[float]) -> None: ...
    def set_velocity(self, node: str, v: Vec3 = ..., omega: Vec3 = ...) -> None: ...
    def set_stroke(self, target: str, dof_or_mode: Union[str, int], value: float) -> None: ...
    def add_freedom(
        self,
        body: str,
        translation: Optional[Vec3] = ...,
        *,
        axis: Optional[Vec3] = ...,
        point: Vec3 = ...,
        pitch: float = ...,
    ) -> None: ...
    def remove_freedom(self, body: str) -> None: ...
    def remove_node(self, name: str) -> None: ...
    def remove_element(self, name: str) -> None: ...
    def remove_material(self, name: str) -> None: ...
    def remove_section(self, name: str) -> None: ...
    def remove_fix(self, node: str) -> None: ...
    def remove_input(self, node: str) -> None: ...
    def remove_loads(self, node: str) -> None: ...
    def remove_mass(self, node: str) -> None: ...
    def remove_inertia(self, node: str) -> None: ...
    def remove_velocity(self, node: str) -> None: ...
    def remove_stroke(self, target: str, dof_or_mode: Union[str, int]) -> None: ...
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
        tangent_eigenvalues: bool = False,
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
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...
