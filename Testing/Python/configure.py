"""The one helper the Python tests share: a VTK filter set up from keyword
settings, the way the tests and benchmarks describe their runs."""


def configured(f, source=None, update=True, **settings):
    """f with Set<Key>(value) for every keyword, fed by source (a data
    object or an algorithm; None: left as it is), updated unless update is
    False.  Returns f."""
    if source is not None:
        if hasattr(source, "GetOutputPort"):
            f.SetInputConnection(source.GetOutputPort())
        else:
            f.SetInputData(source)
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    if update:
        f.Update()
    return f
