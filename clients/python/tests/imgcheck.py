"""SSIM of two RGB images (numpy arrays), the same measure as render/image's
lc_image_ssim: Rec. 709 luminance in [0, 1], an 11x11 Gaussian window
(sigma 1.5) filtered separably over the valid positions, the usual constants."""
import numpy as np


def _filter(img, k):
    n = len(k)
    rows = sum(k[i] * img[:, i:img.shape[1] - n + 1 + i] for i in range(n))
    return sum(k[i] * rows[i:rows.shape[0] - n + 1 + i, :] for i in range(n))


def ssim(a, b):
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    assert a.shape == b.shape, "shapes differ: %s vs %s" % (a.shape, b.shape)
    w = np.array([0.2126, 0.7152, 0.0722]) / 255.0
    x, y = a[..., :3] @ w, b[..., :3] @ w
    t = np.arange(11) - 5
    k = np.exp(-t * t / (2 * 1.5 * 1.5))
    k /= k.sum()
    mx, my = _filter(x, k), _filter(y, k)
    sxx = _filter(x * x, k) - mx * mx
    syy = _filter(y * y, k) - my * my
    sxy = _filter(x * y, k) - mx * my
    c1, c2 = 0.01 ** 2, 0.03 ** 2
    s = ((2 * mx * my + c1) * (2 * sxy + c2)) / ((mx * mx + my * my + c1) * (sxx + syy + c2))
    return float(s.mean())
