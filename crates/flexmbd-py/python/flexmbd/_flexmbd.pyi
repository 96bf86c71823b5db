"""Type stubs of the extension module flexmbd._flexmbd (use it through the package flexmbd)."""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

Array = npt.NDArray[np.float64]

class CoreModel:
    """The compiled model that flexmbd.Model wraps."""

    def source(self) -> Tuple[str, str, str]: ...
    @property
    def name(self) -> str: ...
    @property
    def file(self) -> str: ...
    @property
    def format(self) -> str: ...
    @property
    def node_names(self) -> List[str]: ...
    @property
    def element_names(self) -> List[str]: ...
    @property
    def element_types(self) -> List[str]: ...
    @property
    def n_coordinates(self) -> int: ...
    @property
    def n_deformations(self) -> int: ...
    @property
    def coordinate_names(self) -> List[str]: ...
    @property
    def warnings(self) -> List[str]: ...

class Document:
    """An editable model document (flexmbd.Model wraps it); items arrive as JSON."""

    @staticmethod
    def empty(name: str, file: str) -> Document: ...
    @staticmethod
    def from_json(json: str, file: str, source: Optional[str]) -> Document: ...
    def to_json(self) -> str: ...
    def to_toml(self) -> str: ...
    def copy(self) -> Document: ...
    @property
    def file(self) -> str: ...
    @property
    def source(self) -> Optional[str]: ...
    def summary(self) -> Tuple[str, int, int]: ...
    def core(self) -> CoreModel: ...
    def get(self, path: str) -> str: ...
    def set(self, path: str, json: str) -> None: ...
    def add(self, kind: str, name: str, json: str) -> None: ...
    def replace(self, kind: str, name: str, json: str) -> None: ...
    def put(self, kind: str, name: str, json: str) -> None: ...
    def remove(self, kind: str, name: str) -> None: ...
    def remove_stroke(self, name: str, json: str) -> None: ...

def load(path: str) -> Any:
    """A Document for a .toml file, a CoreModel for a SPACAR .dat file."""

def parse_toml(text: str, file: str) -> Document: ...
def parse(text: str, file: str, format: str) -> CoreModel: ...

class States:
    """States by node and by element, the state (load step or output time) first."""

    def __len__(self) -> int: ...
    @property
    def node_names(self) -> List[str]: ...
    @property
    def element_names(self) -> List[str]: ...
    @property
    def parameter(self) -> Array:
        """Load factor (statics) or time [s] (simulation) of each state."""
    @property
    def energy(self) -> Array:
        """Elastic energy of each state [J]."""
    @property
    def positions(self) -> Array:
        """(states, nodes, 3) [m]."""
    @property
    def displacements(self) -> Array:
        """(states, nodes, 3) [m]."""
    @property
    def rotations(self) -> Array:
        """(states, nodes, 3) rotation vectors [rad]; NaN for nodes without rotation."""
    @property
    def reaction_forces(self) -> Array:
        """(states, nodes, 3) [N]; NaN where no position is held."""
    @property
    def reaction_moments(self) -> Array:
        """(states, nodes, 3) [N m]; NaN where no rotation is held."""
    @property
    def deformations(self) -> Dict[str, Array]:
        """{element: (states, modes)}."""
    @property
    def stress_resultants(self) -> Dict[str, Array]:
        """{element: (states, modes)}."""
    @property
    def max_stress(self) -> Array:
        """(states, elements) [Pa]; NaN for elements without a section."""

class CheckResult:
    """The result of Model.check()."""

    @property
    def Dcc(self) -> Array:
        """Rows: rigid and input deformations; columns: dependent velocity coordinates."""
    @property
    def singular_values(self) -> Array: ...
    @property
    def rank(self) -> int: ...
    @property
    def rank_tol(self) -> float: ...
    @property
    def rank_threshold(self) -> float: ...
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def row_names(self) -> List[str]: ...
    @property
    def column_names(self) -> List[str]: ...
    @property
    def V(self) -> Array:
        """Motions: null vectors of Dcc, (cols, motions)."""
    @property
    def U(self) -> Array:
        """Self-stress states: null vectors of Dcc^T, (rows, self-stresses)."""
    @property
    def table1_row(self) -> int: ...
    @property
    def classification(self) -> str: ...
    @property
    def n_motions(self) -> int: ...
    @property
    def n_self_stresses(self) -> int: ...
    @property
    def exactly_constrained(self) -> bool: ...
    @property
    def motions(self) -> List[Dict[str, Array]]:
        """Per motion: {node: [vx, vy, vz, wx, wy, wz]}."""
    @property
    def self_stresses(self) -> List[Dict[str, Array]]:
        """Per state: {element: values of its deformation modes}."""
    @property
    def generalised_coordinates(self) -> List[str]: ...
    @property
    def advice(self) -> List[Dict[str, Any]]: ...
    @property
    def auto_chosen(self) -> Optional[List[Dict[str, Any]]]: ...
    def to_dict(self) -> Dict[str, Any]:
        """The document of `flexmbd check --json`."""

class StaticResult:
    """The result of Model.static()."""

    @property
    def states(self) -> States: ...
    @property
    def load_factors(self) -> Array: ...
    @property
    def iterations(self) -> List[int]: ...
    @property
    def compliance(self) -> Dict[str, Array]:
        """{node: (steps, 6, 6)} global axes."""
    @property
    def compliance_local(self) -> Dict[str, Array]: ...
    @property
    def buckling(self) -> Optional[Array]:
        """(steps, count) positive multipliers, NaN-padded."""
    @property
    def unstable_directions(self) -> List[Optional[int]]: ...
    @property
    def stopped(self) -> Optional[Dict[str, Any]]: ...
    def to_dict(self) -> Dict[str, Any]:
        """The document of `flexmbd static --json`."""

class ModesResult:
    """The result of Model.modes()."""

    @property
    def frequencies(self) -> Array:
        """[Hz], NaN for negative eigenvalues."""
    @property
    def eigenvalues(self) -> Array: ...
    @property
    def rigid_body(self) -> List[bool]: ...
    @property
    def classes(self) -> List[str]:
        """Per mode: "intended", "support", "internal" or "rigid_body"."""
    @property
    def body_fractions(self) -> Array:
        """Per mode: share of the kinetic energy in the point masses and inertias (β)."""
    @property
    def released_fractions(self) -> Array:
        """Per mode: share of the strain energy in free/input deformations (ρ); NaN for rigid-body modes."""
    @property
    def shapes(self) -> Array:
        """(modes, nodes, 6): translation and rotation of each node."""
    @property
    def strain_energy(self) -> Array:
        """(modes, elements) fractions."""
    @property
    def kinetic_energy(self) -> Array:
        """(modes, nodes, 2) fractions: translation, rotation."""
    @property
    def load_factor(self) -> float: ...
    @property
    def ndof(self) -> int: ...
    def to_dict(self) -> Dict[str, Any]:
        """The document of `flexmbd modes --json`."""

class StateSpace:
    """The result of Model.state_space()."""

    @property
    def A(self) -> Array: ...
    @property
    def B(self) -> Array: ...
    @property
    def C(self) -> Array: ...
    @property
    def D(self) -> Array: ...
    @property
    def input_names(self) -> List[str]: ...
    @property
    def output_names(self) -> List[str]: ...
    @property
    def state_names(self) -> List[str]: ...
    @property
    def frequencies(self) -> Array: ...
    @property
    def eigenvalues(self) -> Array: ...
    @property
    def damping(self) -> float: ...
    @property
    def dc_gain(self) -> Optional[Array]: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def step(self) -> Tuple[int, float]: ...
    def frequency_response(self, f_hz: npt.ArrayLike) -> npt.NDArray[np.complex128]:
        """(frequencies, outputs, inputs)."""
    def to_dict(self) -> Dict[str, Any]:
        """The document of `flexmbd statespace --json`."""
    def to_control(self) -> Any:
        """A python-control StateSpace (ImportError without the package control)."""

class SimulationResult:
    """The result of Model.simulate()."""

    @property
    def t(self) -> Array: ...
    @property
    def states(self) -> States: ...
    @property
    def velocities(self) -> Array: ...
    @property
    def angular_velocities(self) -> Array: ...
    @property
    def energies(self) -> Dict[str, Array]: ...
    @property
    def stats(self) -> Dict[str, Any]: ...
    @property
    def complete(self) -> bool: ...
    def to_dict(self) -> Dict[str, Any]:
        """The document of `flexmbd simulate --json`."""

def check(model: CoreModel, rank_tol: Optional[float] = ..., auto: bool = ..., max_suggestions: int = ..., method: str = ...) -> CheckResult: ...
def static_(model: CoreModel, steps: Optional[int] = ..., compliance: Sequence[str] = ..., buckling: Optional[int] = ..., tol_force: Optional[float] = ..., tol_disp: Optional[float] = ..., line_search: bool = ..., path: Optional[str] = ...) -> StaticResult: ...
def modes(model: CoreModel, count: int = ..., at_step: Optional[int] = ..., steps: Optional[int] = ..., solver: str = ..., path: Optional[str] = ...) -> ModesResult: ...
def state_space(model: CoreModel, inputs: Sequence[str], outputs: Sequence[str], damping: float = ..., modes: Optional[int] = ..., static_correction: bool = ..., at_step: Optional[int] = ..., steps: Optional[int] = ..., solver: str = ...) -> StateSpace: ...
def simulate(model: CoreModel, t_end: Optional[float] = ..., dt: Optional[float] = ..., fixed_step: bool = ..., rho_inf: Optional[float] = ..., tolerance: Optional[Tuple[float, float]] = ..., output_step: Optional[float] = ...) -> SimulationResult: ...
