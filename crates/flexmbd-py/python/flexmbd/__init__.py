"""flexmbd: exact-constraint design of compliant mechanisms from Python.

Read a model (the native TOML format or a SPACAR ``.dat`` file), then run the analyses of the
``flexmbd`` command line on it, in process::

    import flexmbd
    model = flexmbd.load("examples/folded_sheet_guide_5.toml")
    c = model.check()              # Dcc, its SVD, Table 1 class, motions, self-stresses, advice
    s = model.static(steps=20)     # nonlinear statics: states per load step, reactions, ...
    m = model.modes(count=6)       # natural frequencies and mode shapes about the static state
    ss = model.state_space(inputs=["p:y"], outputs=["p:y"])   # A, B, C, D
    sim = model.simulate(t_end=1.0)                            # time simulation

Results hold NumPy arrays, and ``to_dict()`` gives the document of the command's ``--json``.
The GIL is released while an analysis runs, so threads run analyses in parallel. Errors are
the exception classes below (``ModelError`` with ``file``, ``line`` and ``item``, ...).
See docs/python.md.
"""

import os as _os

from . import _flexmbd
from ._errors import (
    FlexmbdError,
    FlexmbdWarning,
    ModelError,
    NumericalError,
    OptionError,
    PathStoppedError,
    ReadError,
    SimulationStoppedError,
    TooLargeError,
)
from ._flexmbd import (
    CheckResult,
    ModesResult,
    SimulationResult,
    StateSpace,
    StaticResult,
    States,
)

__version__ = _flexmbd.__version__

__all__ = [
    "load",
    "Model",
    "CheckResult",
    "StaticResult",
    "ModesResult",
    "StateSpace",
    "SimulationResult",
    "States",
    "FlexmbdError",
    "ModelError",
    "OptionError",
    "NumericalError",
    "PathStoppedError",
    "SimulationStoppedError",
    "TooLargeError",
    "ReadError",
    "FlexmbdWarning",
]


def load(path):
    """Read a model file: ``.toml`` (docs/model-format.md) or a SPACAR ``.dat`` file.

    The file name (as given) names the model in messages and in ``to_dict()["file"]``.
    Raises ``ModelError`` (with ``file``, ``line``, ``item``) for invalid input and
    ``ReadError`` for a file that cannot be read.
    """
    return Model(_flexmbd.read(_os.fspath(path)))


def _from_source(text, file, format):
    """Rebuild a model from its source (what a pickle of a ``Model`` carries)."""
    return Model(_flexmbd.parse(text, file, format))


class Model:
    """A model read from TOML or SPACAR text, with the analysis settings of its file.

    A model is immutable and holds no global state: it can be shared between threads, and it
    pickles as its source text. Create one with ``flexmbd.load(path)``,
    ``Model.from_toml(text)`` or ``Model.from_dat(text)``.
    """

    __slots__ = ("_core",)

    def __init__(self, core):
        if not isinstance(core, _flexmbd.CoreModel):
            raise TypeError(
                "create a Model with flexmbd.load(path), Model.from_toml(text) or Model.from_dat(text)"
            )
        self._core = core

    @classmethod
    def from_toml(cls, text, file="<string>"):
        """A model from TOML text (docs/model-format.md); ``file`` names it in messages."""
        return cls(_flexmbd.parse(text, file, "toml"))

    @classmethod
    def from_dat(cls, text, file="<string>.dat"):
        """A model from the text of a SPACAR ``.dat`` file; ``file`` names it in messages."""
        return cls(_flexmbd.parse(text, file, "dat"))

    def __reduce__(self):
        return (_from_source, self._core.source())

    def __repr__(self):
        return "<flexmbd.Model {!r} from {}: {} nodes, {} elements>".format(
            self.name, self.file, self.n_nodes, self.n_elements
        )

    # -- what the model holds ------------------------------------------------------------

    @property
    def name(self):
        """The model's name."""
        return self._core.name

    @property
    def file(self):
        """The file name used in messages and reports."""
        return self._core.file

    @property
    def format(self):
        """``"toml"`` or ``"dat"``."""
        return self._core.format

    @property
    def source(self):
        """The source text the model was read from."""
        return self._core.source()[0]

    @property
    def node_names(self):
        """Node names, in model order."""
        return self._core.node_names

    @property
    def element_names(self):
        """Element names, in model order."""
        return self._core.element_names

    @property
    def element_types(self):
        """Element types (``truss``, ``beam``, ``hinge``, ``rigid``), in model order."""
        return self._core.element_types

    @property
    def n_nodes(self):
        """Number of nodes."""
        return len(self._core.node_names)

    @property
    def n_elements(self):
        """Number of elements."""
        return len(self._core.element_names)

    @property
    def n_coordinates(self):
        """Number of nodal coordinates x (positions and Euler parameters)."""
        return self._core.n_coordinates

    @property
    def coordinate_names(self):
        """Names of the nodal coordinates (``node.x`` ... ``node.l3``)."""
        return self._core.coordinate_names

    @property
    def n_deformations(self):
        """Number of deformations e."""
        return self._core.n_deformations

    @property
    def warnings(self):
        """Warnings of reading the file (``file:line: message``)."""
        return self._core.warnings

    # -- analyses ------------------------------------------------------------------------

    def check(self, *, rank_tol=None, auto=False, max_suggestions=6, method="auto"):
        """Kinematic analysis (``flexmbd check``): Dcc, its SVD, the Table 1 class, the
        motions and self-stresses, and verified repair advice.

        rank_tol: relative rank tolerance, s_i counts as zero when s_i <= rank_tol * s_1
            (default sqrt(eps)).
        auto: choose the generalised coordinates automatically (one per motion).
        max_suggestions: the most verified suggestions per motion or self-stress state.
        method: "auto" (the sparse rank-revealing LU when Dcc has more than 2500 rows or
            columns or the dense SVD would not fit in memory), "dense" or "sparse".
        Returns a ``CheckResult``.
        """
        return _flexmbd.check(self._core, rank_tol, auto, max_suggestions, method)

    def static(
        self,
        *,
        steps=None,
        compliance=(),
        buckling=None,
        tol_force=None,
        tol_disp=None,
        line_search=False,
        path=None,
    ):
        """Nonlinear statics (``flexmbd static``) over load steps or by arc length.

        steps: number of load steps (over the model's [static] steps; default 10).
        compliance: node names whose 6 x 6 compliance is reported at every step (added to the
            model's [static] compliance).
        buckling: number of buckling load multipliers per step (0: none).
        tol_force, tol_disp: relative residual and increment tolerances (default 1e-9).
        line_search: backtracking line search in Newton.
        path: "load-steps" or "arc-length" (over the model's [static] path).
        Returns a ``StaticResult``; a path that stops part-way raises ``PathStoppedError``
        whose ``result`` holds the converged steps.
        """
        return _flexmbd.static_(
            self._core,
            steps,
            list(compliance),
            buckling,
            tol_force,
            tol_disp,
            line_search,
            path,
        )

    def modes(self, *, count=10, at_step=None, steps=None, solver="auto", path=None):
        """Natural frequencies and mode shapes (``flexmbd modes``), linearised about a static
        equilibrium (with pre-stress) of the model's loads and strokes.

        count: number of modes.
        at_step: the load step of the static solution to linearise at (default: the last).
        steps: number of load steps of the static solution.
        solver: "auto", "dense" (all modes of the dense matrices) or "sparse" (the lowest
            modes by shift-invert Lanczos).
        path: "load-steps" or "arc-length".
        Returns a ``ModesResult``.
        """
        return _flexmbd.modes(self._core, count, at_step, steps, solver, path)

    def state_space(
        self,
        inputs,
        outputs,
        *,
        damping=0.01,
        modes=None,
        static_correction=False,
        at_step=None,
        steps=None,
        solver="auto",
    ):
        """The linear state-space model A, B, C, D (``flexmbd statespace``) about a static
        equilibrium.

        inputs: "NODE:DIR[:force|moment|motion]" or "ELEMENT:MODE:motion", DIR one of x, y,
            z, rx, ry, rz (forces and moments first in the columns of B, then motions).
        outputs: "NODE:DIR[:disp|vel|acc]", "NODE:DIR:reaction" or
            "ELEMENT:MODE:def|force[:vel|acc]" (the rows of C).
        damping: modal damping ratio of every mode.
        modes: keep only the lowest N modes (default: all modes that carry mass).
        static_correction: add the static flexibility of the dropped modes to D.
        at_step, steps: the static state linearised about.
        solver: "auto", "dense" or "sparse".
        Returns a ``StateSpace``; ``to_control()`` gives a python-control ``StateSpace``.
        """
        if isinstance(inputs, str):
            inputs = [inputs]
        if isinstance(outputs, str):
            outputs = [outputs]
        return _flexmbd.state_space(
            self._core,
            list(inputs),
            list(outputs),
            damping,
            modes,
            static_correction,
            at_step,
            steps,
            solver,
        )

    def simulate(
        self,
        *,
        t_end=None,
        dt=None,
        fixed_step=False,
        rho_inf=None,
        tolerance=None,
        output_step=None,
    ):
        """Nonlinear time simulation (``flexmbd simulate``, generalised-alpha), each option
        over the model's [simulate] settings.

        t_end: end time [s]. dt: first (or fixed) step [s]. fixed_step: no step control.
        rho_inf: spectral radius at infinite frequency in [0, 1] (default 0.9).
        tolerance: (abs, rel) of the step control. output_step: output interval [s].
        Returns a ``SimulationResult``; a run that stops early raises
        ``SimulationStoppedError`` whose ``result`` holds the frames up to then.
        """
        if tolerance is not None:
            tolerance = tuple(float(v) for v in tolerance)
        return _flexmbd.simulate(
            self._core, t_end, dt, fixed_step, rho_inf, tolerance, output_step
        )
