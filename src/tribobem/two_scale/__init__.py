"""Two-scale contact of real-size burls: micro windows give the interface laws, the macro solve
uses them (scenario section ``[two_scale]``).

Modules::

    laws        NormalInterfaceLaw: mean gap, real contact fraction and peak pressure of a rough
                interface against nominal pressure (tabulated, interpolated, inverted).
    micro       MicroWindows and the window tables (periodic windows at asperity resolution),
                cached on disk by a hash of the windows and computed through Dask.
    macro       The macro normal solve with a normal interface law (projected Newton), and the
                scale-separation length p / |grad p|.
    tangential  The tangential interface law (slip against mean shear, per pressure) and the
                macro partial-slip solve with it.

The run kinds call them through :mod:`tribobem.runs.two_scale`.
"""
