"""Python client of the Lucent render daemon: one-shot renders as numpy
arrays, frame-coherent WebSocket sessions, camera paths, server-side movies.

    import lucent
    c = lucent.Client("http://127.0.0.1:8080")
    a = c.render("demo:tornado", size=(640, 480))      # numpy (480, 640, 3)
"""
from .camera import fit, from_url, interpolate, orbit, path, turntable
from .client import Client, LucentWarning, build_request, decode_image
from .schema import LucentError, Schema

__version__ = "0.1.0"
__all__ = ["Client", "LucentError", "LucentWarning", "Schema", "build_request", "decode_image", "fit", "from_url",
           "interpolate", "orbit", "path", "turntable"]
