"""CSS mix-blend-mode compositing of premultiplied layers (Compositing and Blending Level 1)."""
from __future__ import annotations

import numpy as np

from ..jit import njit


def unpremultiply(img: np.ndarray, in_place: bool = False) -> np.ndarray:
    """Straight RGBA (transparent pixels black); ``in_place``: written into ``img``."""
    out = img if in_place else img.copy()
    a = out[..., 3:4]
    np.divide(out[..., :3], a, out=out[..., :3], where=a > 0)
    out[..., :3][np.broadcast_to(a <= 0, out[..., :3].shape)] = 0.0
    return out


def premultiply(img: np.ndarray, in_place: bool = False) -> np.ndarray:
    """Premultiplied RGBA of straight ``img``; ``in_place``: written into ``img``."""
    out = img if in_place else img.copy()
    out[..., :3] *= out[..., 3:4]
    return out


def _lum(c):
    return c[..., 0:1] * 0.3 + c[..., 1:2] * 0.59 + c[..., 2:3] * 0.11


def _clip_color(c):
    lum = _lum(c)
    n = c.min(axis=-1, keepdims=True)
    x = c.max(axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(n < 0, lum + (c - lum) * lum / np.where(lum - n == 0, 1, lum - n), c)
        c = np.where(x > 1, lum + (c - lum) * (1 - lum) / np.where(x - lum == 0, 1, x - lum), c)
    return c


def _set_lum(c, lum):
    return _clip_color(c + (lum - _lum(c)))


def _sat(c):
    return c.max(axis=-1, keepdims=True) - c.min(axis=-1, keepdims=True)


def _set_sat(c, s):
    mx = c.max(axis=-1, keepdims=True)
    mn = c.min(axis=-1, keepdims=True)
    rng = mx - mn
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(rng > 0, (c - mn) * s / np.where(rng == 0, 1, rng), 0.0)
    return out


def _separable(mode, cs, cd):
    if mode == "multiply":
        return cs * cd
    if mode == "screen":
        return cs + cd - cs * cd
    if mode == "overlay":
        return _separable("hard-light", cd, cs)
    if mode == "darken":
        return np.minimum(cs, cd)
    if mode == "lighten":
        return np.maximum(cs, cd)
    if mode == "color-dodge":
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.minimum(1.0, cd / np.maximum(1.0 - cs, 1e-12))
        return np.where(cd == 0, 0.0, np.where(cs >= 1, 1.0, r))
    if mode == "color-burn":
        with np.errstate(divide="ignore", invalid="ignore"):
            r = 1.0 - np.minimum(1.0, (1.0 - cd) / np.maximum(cs, 1e-12))
        return np.where(cd >= 1, 1.0, np.where(cs <= 0, 0.0, r))
    if mode == "hard-light":
        return np.where(cs <= 0.5, cd * 2 * cs, _separable("screen", 2 * cs - 1, cd))
    if mode == "soft-light":
        d = np.where(cd <= 0.25, ((16 * cd - 12) * cd + 4) * cd, np.sqrt(cd))
        return np.where(cs <= 0.5, cd - (1 - 2 * cs) * cd * (1 - cd), cd + (2 * cs - 1) * (d - cd))
    if mode == "difference":
        return np.abs(cs - cd)
    if mode == "exclusion":
        return cs + cd - 2 * cs * cd
    return None


def blend_premultiplied(src: np.ndarray, dst: np.ndarray, mode: str) -> np.ndarray:
    """Result of compositing premultiplied ``src`` onto ``dst`` with blend ``mode``."""
    s, d = unpremultiply(src), unpremultiply(dst)
    cs, sa = s[..., :3], s[..., 3:4]
    cd, da = d[..., :3], d[..., 3:4]
    mixed = _separable(mode, cs, cd)
    if mixed is None:
        if mode == "hue":
            mixed = _set_lum(_set_sat(cs, _sat(cd)), _lum(cd))
        elif mode == "saturation":
            mixed = _set_lum(_set_sat(cd, _sat(cs)), _lum(cd))
        elif mode == "color":
            mixed = _set_lum(cs, _lum(cd))
        elif mode == "luminosity":
            mixed = _set_lum(cd, _lum(cs))
        else:
            mixed = cs
    out = np.empty_like(dst)
    out[..., :3] = (1 - da) * src[..., :3] + (1 - sa) * dst[..., :3] + sa * da * np.clip(mixed, 0, 1)
    out[..., 3:4] = sa + da - sa * da
    return out.astype(dst.dtype)


@njit(cache=True, nogil=True)   # bands composite on threads
def over_scaled(src, dst, oy, ox, factor, use_factor, opacity):
    """Source-over of a layer in place: dst[y + oy, x + ox] = s + dst[y + oy, x + ox]·(1 − s_a),
    where s is src[y, x] times factor[y, x] (clip coverage × mask, when ``use_factor``) times
    ``opacity``, for the pixels src covers. float32 throughout, step by step as numpy's
    ``src *= factor; src *= opacity; dst *= 1 − s_a; dst += src`` rounds; pixels where s is
    zero are skipped (they leave dst as it is), so a small layer on a large band costs its
    pixels, not the band's (one pass instead of five whole-band numpy passes)."""
    one = np.float32(1.0)
    op = np.float32(opacity)
    scale = op < one
    for y in range(src.shape[0]):
        ty = y + oy
        for x in range(src.shape[1]):
            tx = x + ox
            r, g, b, a = src[y, x, 0], src[y, x, 1], src[y, x, 2], src[y, x, 3]
            if r == 0.0 and g == 0.0 and b == 0.0 and a == 0.0:
                continue
            if use_factor:
                f = factor[y, x]
                if f == 0.0:
                    continue
                r, g, b, a = r * f, g * f, b * f, a * f
            if scale:
                r, g, b, a = r * op, g * op, b * op, a * op
            k = one - a
            dst[ty, tx, 0] = dst[ty, tx, 0] * k + r
            dst[ty, tx, 1] = dst[ty, tx, 1] * k + g
            dst[ty, tx, 2] = dst[ty, tx, 2] * k + b
            dst[ty, tx, 3] = dst[ty, tx, 3] * k + a


@njit(cache=True, nogil=True)   # bands composite on threads
def over_rects(src, cov, dst, top, rects, opacities):
    """over_scaled of several layers drawn onto shared buffers (render.draw_run), in one call:
    layer i covers dst's rows rects[i, 0] .. rects[i, 1] - 1 and columns rects[i, 2] ..
    rects[i, 3] - 1, its pixels src[y - top, x], scaled by the clip coverage cov[y - top, x, 3]
    where rects[i, 4] is not 0, and by opacities[i]: over_scaled on views of the shared
    buffers (the coverage its factor), without a copy of each layer and its coverage and a
    Python call each."""
    for i in range(rects.shape[0]):
        y0, y1, x0, x1 = rects[i, 0] - top, rects[i, 1] - top, rects[i, 2], rects[i, 3]
        # (views: over_scaled reads them in place)
        over_scaled(src[y0:y1, x0:x1], dst, rects[i, 0], x0, cov[y0:y1, x0:x1, 3],
                    rects[i, 4] != 0, opacities[i])
