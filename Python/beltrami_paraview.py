"""Beltrami in ParaView: keeps a Surface Line Drawing's camera equal to a
view's, so that its contours and suggestive contours follow the camera while
you rotate (GUI Python shell) or move it from a script (pvpython, pvbatch).

    import beltrami_paraview
    drawing = SurfaceLineDrawing(Input=GetActiveSource())
    Show(drawing)
    stop = beltrami_paraview.follow_camera(drawing, GetActiveView())
    ...
    stop()   # the lines stay where they are from now on

The drawing's CameraPosition, ViewDirection and ParallelProjection are set
whenever the view's camera changes (an observer on its vtkCamera); the next
render re-runs only the drawing's per-view pass.
"""


def _view_of(camera):
    return (tuple(camera.GetPosition()), tuple(camera.GetDirectionOfProjection()),
            1 if camera.GetParallelProjection() else 0, tuple(camera.GetViewUp()))


def follow_camera(drawing, view=None):
    """Makes the SurfaceLineDrawing proxy `drawing` follow the camera of
    `view` (default: the active view).  Returns a function that stops it."""
    if view is None:
        from paraview.simple import GetActiveView
        view = GetActiveView()
    camera = view.GetActiveCamera()
    state = {"view": None}

    def update(*_):
        current = _view_of(camera)
        if current == state["view"]:
            return  # e.g. the clipping range changed while rendering
        state["view"] = current
        drawing.CameraPosition = list(current[0])
        drawing.ViewDirection = list(current[1])
        drawing.ParallelProjection = current[2]
        drawing.ViewUp = list(current[3])

    update()
    tag = camera.AddObserver("ModifiedEvent", update)
    return lambda: camera.RemoveObserver(tag)
