# The peer of `lucent bench` for scripts/bench_peers.sh: renders a .vtk or .ply
# file with ParaView's depth peeling (translucent lines, points or surface) and
# prints the time of each frame, Render() plus a readback of the image into
# memory, as Lucent's wall ms includes its readback.
#
# usage: xvfb-run -a -s "-screen 0 WxHx24" pvpython scripts/bench_paraview.py FILE W H
#            [--frames N] [--warmup N] [--opacity A] [--peels N] [--line-width PX] [--save PNG]
# Prints "renderer: ...", "paraview ...", the representation, then one
# "frame_ms X" line per timed frame. Exit 1 with a message if the file cannot
# be read or holds no geometry.
import argparse
import math
import sys
import time

from paraview import servermanager
from paraview.simple import (ColorBy, CreateView, GetDisplayProperties, OpenDataFile, Render, SetActiveView,
                             Show)
from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

ap = argparse.ArgumentParser(description="ParaView depth-peeling benchmark (peer of lucent bench)")
ap.add_argument("file")
ap.add_argument("width", type=int)
ap.add_argument("height", type=int)
ap.add_argument("--frames", type=int, default=3)
ap.add_argument("--warmup", type=int, default=1)
ap.add_argument("--opacity", type=float, default=0.3)
ap.add_argument("--peels", type=int, default=8)
ap.add_argument("--line-width", type=float, default=0,
                help="pixels; 0 = Lucent's default ribbon width at this height (0.004 x the bounds' diagonal)")
ap.add_argument("--save", metavar="PNG", help="also write the last frame (to compare the pictures)")
a = ap.parse_args()

t0 = time.perf_counter()
reader = OpenDataFile(a.file)
if reader is None:
    sys.exit("bench_paraview.py: %s: ParaView has no reader for this file" % a.file)
reader.UpdatePipeline()
info = reader.GetDataInformation()
load_ms = 1000 * (time.perf_counter() - t0)
if info.GetNumberOfPoints() == 0:
    sys.exit("bench_paraview.py: %s: no points read" % a.file)

view = CreateView("RenderView")
SetActiveView(view)
view.ViewSize = [a.width, a.height]
view.OrientationAxesVisibility = 0
try:  # 5.10+: the colour palette owns the background unless told otherwise
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
view.Background = [1, 1, 1]
view.EnableRenderOnInteraction = 0
view.DepthPeeling = 1
view.MaximumNumberOfPeels = a.peels

disp = Show(reader, view)
# The cell types decide the representation (the builtin session's Fetch is a
# shallow copy): lines and triangles draw as they are in the Surface
# representation, a point cloud (VERTICES or no cells) as points.
data = servermanager.Fetch(reader)
lines = data.GetNumberOfLines() if hasattr(data, "GetNumberOfLines") else 0
polys = data.GetNumberOfPolys() + data.GetNumberOfStrips() if hasattr(data, "GetNumberOfPolys") else 0
cells = info.GetNumberOfCells()
kind = "lines" if lines and lines >= polys else "surface" if polys else "points"
disp.SetRepresentationType("Points" if kind == "points" else "Surface")
disp.Opacity = a.opacity
arrays = [info.GetPointDataInformation().GetArrayInformation(i).GetName()
          for i in range(info.GetPointDataInformation().GetNumberOfArrays())]
if arrays:  # colour through a lookup table, as Lucent colours through a colormap
    ColorBy(disp, ("POINTS", arrays[0]))
    disp.RescaleTransferFunctionToDataRange(True, False)

# Lucent's fitted camera (render/math/camera.c): along -z, +y up, 30 degrees,
# at the distance where the bounds' sphere fills the view.
b = info.GetBounds()
c = [0.5 * (b[2 * i] + b[2 * i + 1]) for i in range(3)]
radius = math.sqrt(sum((0.5 * (b[2 * i + 1] - b[2 * i])) ** 2 for i in range(3))) or 0.5
dist = radius / math.sin(math.radians(15))
view.CameraFocalPoint = c
view.CameraPosition = [c[0], c[1], c[2] + dist]
view.CameraViewUp = [0, 1, 0]
view.CameraViewAngle = 30
view.CameraParallelProjection = 0
# Lucent's default ribbon is 0.004 x the diagonal (2 radius) wide in world
# units; at the focal distance the view spans 2 radius / cos(15 deg).
line_px = a.line_width or max(1.0, 0.004 * math.cos(math.radians(15)) * a.height)
disp.LineWidth = line_px
disp.PointSize = 2

rw = view.GetRenderWindow()
grab = vtkWindowToImageFilter()
grab.SetInput(rw)
grab.ReadFrontBufferOff()
grab.ShouldRerenderOff()
grab.SetInputBufferTypeToRGBA()


def pv_version():
    pm = servermanager.vtkSMProxyManager
    return "%d.%d.%d" % (pm.GetVersionMajor(), pm.GetVersionMinor(), pm.GetVersionPatch())


def frame():
    Render(view)
    grab.Modified()
    grab.Update()
    return grab.GetOutput()


img = frame()
caps = rw.ReportCapabilities() or ""
renderer = next((l.split(":", 1)[1].strip() for l in caps.splitlines() if "OpenGL renderer string" in l), "unknown")
glver = next((l.split(":", 1)[1].strip() for l in caps.splitlines() if "OpenGL version string" in l), "")
print("renderer: %s | %s" % (renderer, glver))
print("ParaView %s, %s, %d points, %d cells, load %.0f ms" % (pv_version(),
                                                            kind, info.GetNumberOfPoints(), cells, load_ms))
print("%dx%d, opacity %.2f, depth peeling %d peels, line width %.1f px, %d frames (+%d warm-up)" %
      (a.width, a.height, a.opacity, a.peels, line_px, a.frames, a.warmup))
dims = img.GetDimensions()
if dims[0] != a.width or dims[1] != a.height:
    sys.exit("bench_paraview.py: the window is %dx%d, not %dx%d (a larger X screen is needed)" %
             (dims[0], dims[1], a.width, a.height))
for _ in range(max(0, a.warmup - 1)):  # the first frame above was one warm-up frame
    frame()
for _ in range(a.frames):
    t = time.perf_counter()
    frame()
    print("frame_ms %.2f" % (1000 * (time.perf_counter() - t)), flush=True)
if a.save:
    from vtkmodules.vtkIOImage import vtkPNGWriter
    w = vtkPNGWriter()
    w.SetFileName(a.save)
    w.SetInputData(grab.GetOutput())
    w.Write()
