"""StateSpace.to_control(): the state-space model as a python-control ``StateSpace``."""


def to_control(ss):
    """Return ``control.StateSpace(A, B, C, D)`` with the input, output and state names."""
    try:
        import control
    except ImportError as e:
        raise ImportError(
            "StateSpace.to_control() needs the package python-control: "
            "pip install control (or pip install 'flexmbd[control]')"
        ) from e
    kwargs = dict(inputs=ss.input_names, outputs=ss.output_names, states=ss.state_names)
    try:
        return control.StateSpace(ss.A, ss.B, ss.C, ss.D, **kwargs)
    except TypeError:
        # python-control before 0.9.x: no signal names
        return control.StateSpace(ss.A, ss.B, ss.C, ss.D)
