"""Pipelines and pictures shared by the demo (Examples/) and the tests
(Testing/Python/): curvatures and their picture, the parameterization and a
checkerboard mapped by it, image I/O between PNG files, numpy and
vtkImageData, the image flow with the settings for a noise level, and the
noisy scans of the smoothing demo.

>>> from beltrami import pipelines
>>> curvatures, seconds = pipelines.compute_curvatures("Testing/Data/bunny00.off")
>>> pipelines.render_mean_curvature(curvatures, "bunny.png")   # off screen
"""
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLookupTable, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkPolyDataNormals
from vtkmodules.vtkImagingSources import vtkImageCanvasSource2D
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
from vtkmodules.vtkRenderingCore import (vtkActor, vtkColorTransferFunction, vtkPolyDataMapper,
                                         vtkRenderer, vtkRenderWindow, vtkTexture, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (rendering backend)

from .BeltramiFilters import (vtkDiscreteCurvatures, vtkImageBeltramiDenoising, vtkIntrinsicParameterization,
                              vtkSurfaceAtlas, vtkSurfaceLineDrawing, vtkSurfaceRemeshing)
from .BeltramiIO import vtkOFFReader

SIGMA = 0.1  # the noise level of the denoising demo and tests
SEED = 1234


def compute_curvatures(mesh_path):
    curvatures, elapsed = run_on_off(mesh_path, vtkDiscreteCurvatures())
    return curvatures.GetOutput(), elapsed


def curvature_range(values, percentile=98.0):
    """Symmetric colour range that ignores NaN and the noisiest 2% of points."""
    finite = np.abs(values[np.isfinite(values)])
    limit = float(np.percentile(finite, percentile)) if finite.size else 1.0
    return -limit, limit


def render_mean_curvature(polydata, png_path, size=(800, 800)):
    """Renders MeanCurvature with a diverging colour map (blue concave, red convex)."""
    values = vtk_to_numpy(polydata.GetPointData().GetArray("MeanCurvature"))
    low, high = curvature_range(values)
    lut = vtkColorTransferFunction()
    lut.SetColorSpaceToDiverging()
    lut.AddRGBPoint(low, 0.23, 0.30, 0.75)
    lut.AddRGBPoint(0.5 * (low + high), 0.87, 0.87, 0.87)
    lut.AddRGBPoint(high, 0.71, 0.02, 0.15)
    lut.SetNanColor(1.0, 1.0, 0.0)

    mapper = vtkPolyDataMapper()
    mapper.SetInputData(polydata)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray("MeanCurvature")
    mapper.SetLookupTable(lut)
    mapper.SetColorModeToMapScalars()
    mapper.ScalarVisibilityOn()
    mapper.SetScalarRange(low, high)
    actor = vtkActor()
    actor.SetMapper(mapper)

    return snapshot(actor, png_path, size, view_up=(0, 1, 0), zoom=1.3)


def snapshot(actor, png_path, size, view_up=(0, 1, 0), direction=(0, 0, 1), zoom=1.0):
    """Renders one actor off screen on white, writes the PNG, returns the image."""
    return capture(framed_renderer([actor], view_up, direction, zoom), png_path, size)


def framed_renderer(actors, view_up=(0, 1, 0), direction=(0, 0, 1), zoom=1.0):
    """A renderer on white with the actors, its camera looking at them from
    `direction` (the actors framed, then zoomed)."""
    renderer = vtkRenderer()
    for actor in actors:
        renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*direction)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(*view_up)
    renderer.ResetCamera()
    camera.Zoom(zoom)
    return renderer


def capture(renderer, png_path, size):
    """Renders off screen, writes the PNG, returns the image."""
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    return write_png_of(grab, png_path)


def write_png_of(algorithm, png_path):
    """Writes an image algorithm's output as a PNG; returns the image."""
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(algorithm.GetOutputPort())
    writer.Write()
    return algorithm.GetOutput()


def write_vtp(polydata, path):
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(polydata)
    writer.Write()


def run_on_off(mesh_path, f):
    """Runs the filter `f` on the OFF mesh at `mesh_path` (read first, not
    timed); returns (f, seconds of f's update)."""
    reader = vtkOFFReader()
    reader.SetFileName(mesh_path)
    reader.Update()
    f.SetInputConnection(reader.GetOutputPort())
    start = time.perf_counter()
    f.Update()
    return f, time.perf_counter() - start


def parameterize(mesh_path, conformal=1.0, authalic=0.0, boundary=vtkIntrinsicParameterization.NATURAL):
    f = vtkIntrinsicParameterization()
    f.SetConformalWeight(conformal)
    f.SetAuthalicWeight(authalic)
    f.SetBoundary(boundary)
    return run_on_off(mesh_path, f)


def surface_atlas(mesh_path, charts=0, split_at_features=False):
    """vtkSurfaceAtlas on an OFF mesh (sharp edges kept as chart boundaries
    on request); returns (filter, seconds)."""
    f = vtkSurfaceAtlas()
    f.SetNumberOfCharts(charts)
    f.SetSplitAtFeatures(split_at_features)
    return run_on_off(mesh_path, f)


def remesh(mesh_path, vertices=10000, importance=0, gamma=1.0, split_at_features=False, gradation=0.0,
           transfer_function=(), anisotropy=0, maximum_deviation=0.0):
    """vtkSurfaceRemeshing on an OFF mesh (importance: vtkSurfaceRemeshing's
    UNIFORM, MEAN_CURVATURE, ...; transfer_function: (x, importance) pairs
    used instead of gamma; anisotropy: ISOTROPIC, PRINCIPAL_CURVATURES;
    maximum_deviation > 0: the error-driven mode, `vertices` its least
    count); returns (filter, seconds)."""
    f = vtkSurfaceRemeshing()
    f.SetNumberOfVertices(vertices)
    f.SetImportance(importance)
    f.SetGamma(gamma)
    f.SetSplitAtFeatures(split_at_features)
    f.SetGradation(gradation)
    f.SetAnisotropy(anisotropy)
    f.SetMaximumDeviation(maximum_deviation)
    for x, y in transfer_function:
        f.AddTransferFunctionPoint(x, y)
    return run_on_off(mesh_path, f)


def wireframe_actor(polydata):
    """The surface in a light colour with its edges drawn."""
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(polydata)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.93, 0.86, 0.70)
    actor.GetProperty().EdgeVisibilityOn()
    actor.GetProperty().SetEdgeColor(0.15, 0.15, 0.15)
    return actor


def render_wireframe(polydata, png_path, size=(800, 800), view_up=(0, 1, 0), direction=(0, 0.2, 1), zoom=1.0):
    """The surface in a light colour with its edges drawn (a remesh's
    triangles)."""
    return snapshot(wireframe_actor(polydata), png_path, size, view_up=view_up, direction=direction, zoom=zoom)


def render_side_by_side(meshes, png_path, size=(1200, 600), gap=0.2, view_up=(0, 1, 0), direction=(0, 0, 1),
                        zoom=1.9):
    """Meshes in wireframe side by side at one scale, left to right as the
    camera (looking from `direction`) sees them, `gap` (the meshes' units)
    apart."""
    up, towards = np.array(view_up, float), np.array(direction, float)
    right = np.cross(up, towards)
    right /= np.linalg.norm(right)
    actors, x = [], 0.0
    for mesh in meshes:
        corners = np.array(np.meshgrid(*np.array(mesh.GetBounds()).reshape(3, 2), indexing="ij")).reshape(3, -1).T
        extent = corners @ right
        actor = wireframe_actor(mesh)
        actor.SetPosition(*((x - extent.min()) * right))
        actors.append(actor)
        x += extent.max() - extent.min() + gap
    return capture(framed_renderer(actors, view_up, direction, zoom), png_path, size)


def render_flat_meshes(meshes, png_path, size=(1200, 600), gap=0.2):
    """Flat meshes (points (u, v, 0)) side by side at one scale, left to right."""
    return render_side_by_side(meshes, png_path, size, gap)


# Colours of vtkSurfaceLineDrawing's line types (contour, suggestive contour,
# suggestive highlight, ridge, valley, boundary, crease, apparent ridge).
LINE_COLOURS = ((0.0, 0.0, 0.0), (0.10, 0.25, 0.75), (0.95, 0.55, 0.05), (0.80, 0.10, 0.10),
                (0.10, 0.55, 0.20), (0.0, 0.0, 0.0), (0.35, 0.35, 0.35), (0.55, 0.15, 0.65))


def line_drawing(mesh_path, ridges=False, valleys=False, highlights=False, minimum_length=0.0, hysteresis=1.0,
                 smoothing=0.0):
    """vtkSurfaceLineDrawing on an OFF mesh (contours, suggestive contours,
    boundaries and creases; ridges, valleys and highlights on request;
    lines shorter than minimum_length feature sizes dropped, curvature lines
    traced down to hysteresis times their thresholds where they pass them,
    the curvatures measured on a copy smoothed over `smoothing` feature
    sizes: by default every piece of the surface's own lines, 0, 1 and 0,
    where the filter's defaults are 2, 0.5 and 0.5);
    returns the filter, not yet updated: its camera is set by
    render_line_drawing."""
    reader = vtkOFFReader()
    reader.SetFileName(mesh_path)
    drawing = vtkSurfaceLineDrawing()
    drawing.SetInputConnection(reader.GetOutputPort())
    drawing.SetRidges(ridges)
    drawing.SetValleys(valleys)
    drawing.SetSuggestiveHighlights(highlights)
    drawing.SetMinimumLineLength(minimum_length)
    drawing.SetHysteresisRatio(hysteresis)
    drawing.SetCurvatureSmoothing(smoothing)
    return drawing


def follow(drawing, camera):
    """Sets the drawing's view to the camera's (vtkCamera)."""
    drawing.SetCameraPosition(camera.GetPosition())
    drawing.SetViewDirection(camera.GetDirectionOfProjection())
    drawing.SetParallelProjection(bool(camera.GetParallelProjection()))
    drawing.SetViewUp(camera.GetViewUp())


def write_print_drawing(drawing, stem, hidden_dashed=False):
    """Writes the drawing's visible lines (for its current camera) as
    stem.svg and stem.pdf with vtkLineDrawingWriter (hidden lines dashed
    when asked); the drawing's Visibility is left as it was."""
    from beltrami import vtkLineDrawingWriter
    before = drawing.GetVisibility()
    drawing.SetVisibility(vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES if hidden_dashed
                          else vtkSurfaceLineDrawing.VISIBLE_LINES)
    writer = vtkLineDrawingWriter()
    writer.SetInputConnection(drawing.GetOutputPort())
    writer.SetDrawHiddenLines(hidden_dashed)
    for extension in (".svg", ".pdf"):
        writer.SetFileName(stem + extension)
        writer.Write()
    drawing.SetVisibility(before)
    return [stem + ".svg", stem + ".pdf"]


def white_surface_actor(source):
    """A white surface (poly data, or an algorithm's output port) drawn
    behind lines on it (polygon offset)."""
    surface_mapper = vtkPolyDataMapper()
    if hasattr(source, "GetNumberOfCells"):
        surface_mapper.SetInputData(source)
    else:
        surface_mapper.SetInputConnection(source)
    surface_mapper.ScalarVisibilityOff()
    surface_mapper.SetResolveCoincidentTopologyToPolygonOffset()
    surface_mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(2.0, 2.0)
    surface = vtkActor()
    surface.SetMapper(surface_mapper)
    surface.GetProperty().SetColor(1.0, 1.0, 1.0)
    surface.GetProperty().SetAmbient(0.35)
    surface.GetProperty().SetDiffuse(0.65)
    return surface


def line_type_actor(lines, line_width=2.0):
    """The polylines of a line drawing coloured by their LineType."""
    colours = vtkLookupTable()
    colours.SetNumberOfTableValues(len(LINE_COLOURS))
    for i, rgb in enumerate(LINE_COLOURS):
        colours.SetTableValue(i, *rgb, 1.0)
    colours.SetTableRange(0, len(LINE_COLOURS) - 1)
    lines_mapper = vtkPolyDataMapper()
    lines_mapper.SetInputData(lines)
    lines_mapper.SetScalarModeToUseCellFieldData()
    lines_mapper.SelectColorArray("LineType")
    lines_mapper.SetLookupTable(colours)
    lines_mapper.SetColorModeToMapScalars()
    lines_mapper.SetScalarRange(0, len(LINE_COLOURS) - 1)
    actor = vtkActor()
    actor.SetMapper(lines_mapper)
    actor.GetProperty().SetLineWidth(line_width)
    actor.GetProperty().LightingOff()
    return actor


def render_line_drawing(drawing, png_path, size=(800, 800), view_up=(0, 1, 0), direction=(0, 0, 1), zoom=1.0,
                        line_width=2.0):
    """The drawing's lines over its surface in white, for a camera looking
    from `direction`: the drawing is updated for that camera first.
    Returns (image, seconds of the drawing's update)."""
    drawing.GetInputAlgorithm().Update()
    renderer = framed_renderer([white_surface_actor(drawing.GetInputConnection(0, 0))], view_up, direction, zoom)
    follow(drawing, renderer.GetActiveCamera())
    start = time.perf_counter()
    drawing.Update()
    elapsed = time.perf_counter() - start
    renderer.AddActor(line_type_actor(drawing.GetOutput(), line_width))
    return capture(renderer, png_path, size), elapsed


def render_visible_lines(drawing, png_path, size=(800, 800), view_up=(0, 1, 0), direction=(0, 0, 1), zoom=1.0,
                         line_width=2.0):
    """The drawing's lines alone, no surface to hide them, for a camera
    looking from `direction` with its Visibility set to visible and hidden
    lines: visible lines black, hidden ones light grey. Returns the image."""
    drawing.GetInputAlgorithm().Update()
    surface = white_surface_actor(drawing.GetInputConnection(0, 0))
    renderer = framed_renderer([surface], view_up, direction, zoom)
    renderer.RemoveActor(surface)  # (it framed the camera)
    follow(drawing, renderer.GetActiveCamera())
    drawing.SetVisibility(vtkSurfaceLineDrawing.VISIBLE_AND_HIDDEN_LINES)
    drawing.Update()
    colours = vtkLookupTable()
    colours.SetNumberOfTableValues(2)
    colours.SetTableValue(0, 0.0, 0.0, 0.0, 1.0)
    colours.SetTableValue(1, 0.75, 0.75, 0.75, 1.0)
    colours.SetTableRange(0, 1)
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(drawing.GetOutput())
    mapper.SetScalarModeToUseCellFieldData()
    mapper.SelectColorArray("Hidden")
    mapper.SetLookupTable(colours)
    mapper.SetColorModeToMapScalars()
    mapper.SetScalarRange(0, 1)
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetLineWidth(line_width)
    actor.GetProperty().LightingOff()
    renderer.AddActor(actor)
    return capture(renderer, png_path, size)


def rasterise_svg(svg_path, png_path, width=400):
    """An SVG page as a PNG `width` pixels wide on white (rsvg-convert, from
    Debian's librsvg2-bin); returns the RGB image."""
    import subprocess
    from vtkmodules.vtkImagingCore import vtkImageExtractComponents
    subprocess.run(["rsvg-convert", "-w", str(width), "-b", "white", "-o", png_path, svg_path], check=True)
    reader = vtkPNGReader()
    reader.SetFileName(png_path)
    rgb = vtkImageExtractComponents()
    rgb.SetInputConnection(reader.GetOutputPort())
    rgb.SetComponents(0, 1, 2)
    rgb.Update()
    return write_png_of(rgb, png_path)


def checkerboard(squares=16, pixels=32):
    """A black-and-white checkerboard image, `squares` squares per side."""
    canvas = vtkImageCanvasSource2D()
    size = squares * pixels
    canvas.SetExtent(0, size - 1, 0, size - 1, 0, 0)
    canvas.SetScalarTypeToUnsignedChar()
    canvas.SetNumberOfScalarComponents(3)
    canvas.SetDrawColor(245, 245, 245)
    canvas.FillBox(0, size - 1, 0, size - 1)
    canvas.SetDrawColor(40, 60, 140)
    for i in range(squares):
        for j in range(squares):
            if (i + j) % 2:
                canvas.FillBox(i * pixels, (i + 1) * pixels - 1, j * pixels, (j + 1) * pixels - 1)
    canvas.Update()
    return canvas.GetOutput()


def render_checkerboard(polydata, png_path, size=(800, 800), squares=16, view_up=(0, 0, 1), direction=(1, -1, 0.6)):
    """The surface with a checkerboard mapped through its TCoords."""
    return render_textured(polydata, checkerboard(squares), png_path, size, view_up, direction)


def render_textured(polydata, image, png_path, size=(800, 800), view_up=(0, 0, 1), direction=(1, -1, 0.6)):
    """The surface with the image (vtkImageData, RGB) mapped through its TCoords."""
    texture = vtkTexture()
    texture.SetInputData(image)
    texture.InterpolateOff()
    texture.RepeatOff()
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(polydata)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.SetTexture(texture)
    return snapshot(actor, png_path, size, view_up=view_up, direction=direction, zoom=1.2)


def diverging_colours(values, background=(255, 255, 255)):
    """(h, w) values -> (h, w, 3) uint8 in the diverging map of
    render_mean_curvature (blue negative, red positive, over the symmetric
    range of curvature_range); NaN in `background`."""
    low, high = curvature_range(values)
    t = np.clip((np.nan_to_num(values) - low) / (high - low), 0.0, 1.0)[..., None]
    blue, grey, red = np.array([0.23, 0.30, 0.75]), np.array([0.87, 0.87, 0.87]), np.array([0.71, 0.02, 0.15])
    rgb = np.where(t < 0.5, blue + 2 * t * (grey - blue), grey + (2 * t - 1) * (red - grey))
    rgb = np.round(255 * rgb).astype(np.uint8)
    rgb[~np.isfinite(values)] = background
    return rgb


def atlas_texture(atlas_filter, name="MeanCurvature", resolution=1024):
    """The point array `name` baked into the atlas texture: the filter's maps
    as one atlas image (MapLayout ATLAS) at resolution^2 texels, coloured by
    diverging_colours; returns the (h, w, 3) uint8 array, top row first."""
    atlas_filter.SetMapLayout(vtkSurfaceAtlas.ATLAS)
    atlas_filter.SetMapResolution(resolution)
    atlas_filter.Update()
    maps = atlas_filter.GetOutputDataObject(1)
    values = from_image(maps.GetBlock(0), name)[..., 0]
    return pad_charts(diverging_colours(values), np.isfinite(values))


def pad_charts(rgb, inside, texels=2):
    """Texels outside the charts (within `texels` of one) take the colour of
    a neighbour inside, so that a texture lookup at a chart's edge never
    reads the background (the seams would show as lines)."""
    rgb, inside = rgb.copy(), inside.copy()
    for _ in range(texels):
        grown = inside.copy()
        for axis, step in ((0, 1), (0, -1), (1, 1), (1, -1)):
            source = np.roll(inside, step, axis)
            take = ~grown & source
            rgb[take] = np.roll(rgb, step, axis)[take]
            grown |= take
        inside = grown
    return rgb


def read_png(path):
    """The PNG file `path` as an (h, w, components) uint8 array, top row first."""
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[::-1].copy()


def to_image(a, name="values"):
    """(h, w, components) array, top row first -> vtkImageData (VTK's rows go up)."""
    h, w, nc = a.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    values = numpy_to_vtk(np.ascontiguousarray(a[::-1].reshape(h * w, nc)), deep=1)
    values.SetName(name)
    image.GetPointData().SetScalars(values)
    return image


def from_image(image, name="values"):
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetArray(name)).reshape(h, w, -1)[::-1].copy()


def noisy_version(clean8, sigma=SIGMA, seed=SEED):
    """8-bit image plus Gaussian noise of sigma * 255, rounded and clipped to 8 bits."""
    noise = np.random.default_rng(seed).normal(0.0, 255.0 * sigma, clean8.shape)
    return np.clip(np.round(clean8 + noise), 0, 255).astype(np.uint8)


def denoise(noisy8, threads=0, **settings):
    """The Beltrami flow at its defaults (no parameter set: the noise level is
    estimated from the image, the contrast scale follows from it and the flow
    stops at the least estimated error); uint8 in and out.  `settings`: other
    vtkImageBeltramiDenoising settings by name (ColorSpace=..., ...)."""
    f = vtkImageBeltramiDenoising()
    f.SetInputData(to_image(noisy8))
    f.SetNumberOfThreads(threads)
    for key, value in settings.items():
        getattr(f, "Set" + key)(value)
    f.Update()
    return from_image(f.GetOutput()), f.GetOutput().GetFieldData()


def psnr(a, b):
    return 10 * np.log10(255.0 ** 2 / np.mean((a.astype(float) - b.astype(float)) ** 2))


def write_png(a, png_path):
    """(h, w, components) uint8 array, top row first -> PNG file."""
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputData(to_image(a))
    writer.Write()


def write_side_by_side(left, right, png_path):
    write_png(np.concatenate([left, np.full((left.shape[0], 8, left.shape[2]), 255, np.uint8), right], axis=1),
              png_path)


def noisy_along_normals(polydata, sigma, seed):
    """A copy of polydata with Gaussian noise of standard deviation sigma
    along the (unsplit) point normals: a synthetic noisy scan."""
    normals = vtkPolyDataNormals()
    normals.SplittingOff()
    normals.SetInputData(polydata)
    normals.Update()
    n = vtk_to_numpy(normals.GetOutput().GetPointData().GetNormals()).astype(float)
    x = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    return with_points(polydata, x + (sigma * np.random.default_rng(seed).standard_normal(len(x)))[:, None] * n)


def noisy_isotropic(polydata, sigma, seed):
    """A copy of polydata with Gaussian noise of standard deviation sigma in
    each coordinate: a scan's noise in every direction."""
    x = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    return with_points(polydata, x + sigma * np.random.default_rng(seed).standard_normal(x.shape))


def with_points(polydata, x):
    """A copy of polydata with the points x (n x 3)."""
    copy = vtkPolyData()
    copy.DeepCopy(polydata)
    points = vtkPoints()
    points.SetData(numpy_to_vtk(np.ascontiguousarray(x, dtype=float), deep=1))
    copy.SetPoints(points)
    return copy


def rms_distance(polydata, clean_points):
    """RMS vertex-to-vertex distance to the clean points."""
    x = vtk_to_numpy(polydata.GetPoints().GetData()).astype(float)
    return float(np.sqrt(np.mean(np.sum((x - clean_points) ** 2, 1))))
