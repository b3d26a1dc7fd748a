"""Decoding the server's PNG/JPEG frames (PIL, numpy)."""
import io


def decode_image(data, mode="array"):
    """Image bytes (PNG/JPEG) as a numpy array (H, W, 3) uint8, or a PIL image
    (mode "pil")."""
    from PIL import Image
    img = Image.open(io.BytesIO(data))
    img.load()
    img = img.convert("RGB")
    if mode == "pil":
        return img
    import numpy as np
    return np.asarray(img)
