"""Light directions: CloudCompare's equal-area set (qPCV), after Leopardi's zonal partition.

Leopardi's recursive zonal equal area (EQ) partition divides the unit sphere into ``N``
regions of equal area ``A = 4 pi / N`` (Leopardi 2006).  CloudCompare 2.11.3's qPCV takes
the centre of each region as a light direction; with "northern hemisphere only" (its
default) it partitions ``N = 2 * rays`` and keeps the directions with light coming from +z.
What follows was established from its behaviour (a cube's shadows on a floor seen through
its per-vertex values, directions recovered to about 0.05 degrees), never from its code:

1. Two polar caps of area ``A``: colatitude ``2 asin(1 / sqrt(N))``; the north cap's
   direction is +z.
2. The band between them is cut into collars: the band's angular width over the side of an
   ideal square region ``sqrt(A)``, *rounded up* (Leopardi's rounds to the nearest), each
   first of equal angular width.
3. Each collar holds its ideal number of regions (its area over ``A``) *rounded on its own*
   (Leopardi carries each rounding error to the next collar, so that the counts add up to
   ``N``; CloudCompare does not: 256 rays give a second collar of 13 where Leopardi's has
   12).  The boundaries then move so that the first ``j`` regions fill a cap of ``j``
   shares of the sphere, a share being its area over the counts' total (``A`` when they
   add up to ``N``; 2,046 regions for 1,024 rays).
4. A collar's directions lie at the mean of its two boundary colatitudes, on equally
   spaced longitudes.
5. With the hemisphere, the directions strictly north of the equator are kept: an odd
   number of collars puts the middle one on the equator, and it is dropped.  256 rays give
   236 directions, 1024 give 984.

Steps 1-5 hold for every ray count probed (3-6, 8, 9, 11-16, 20, 25, 256, 1024), except 7
and 10, whose first collars CloudCompare fills with 3 and 6 directions (the rule gives 4
and 5).  Where each collar's longitudes start follows no rule found (neither Leopardi's
offsets between collars, nor a turn of the whole set, nor a pseudo-random sequence): at
CloudCompare's default, 256 rays over the northern hemisphere, they are its measured
values (:data:`QPCV_256_LONGITUDES`); at other counts, Leopardi's offsets, which stagger
neighbouring collars the same way.  There the directions are CloudCompare's in number and
colatitude but not in longitude: the crown means agree (within 0.1 % at 1024 rays on the
shared crowns), single vertices less closely.

May import: nothing of dentopo.
"""

from __future__ import annotations

import math

import numpy as np

#: A centre this close to the equator (in z) lies on it: the hemisphere rule drops it.
EQUATOR = 1e-9

#: CloudCompare 2.11.3's longitude of the first direction of each collar north of the
#: equator (degrees, mod the collar's spacing), at its default 256 rays over the northern
#: hemisphere, north to south (collars of 7, 13, 18, 24, 28, 32, 36, 38 and 39 directions):
#: the mean of two shadow probes, which agree within 0.05 degrees.
QPCV_256_LONGITUDES = (46.85, 13.24, 12.46, 4.99, 10.29, 7.90, 1.04, 5.51, 6.60)


def _cap_colatitude(area: float) -> float:
    """Colatitude of the polar cap of S^2 with this area."""
    return 2.0 * math.asin(min(1.0, math.sqrt(area / math.pi) / 2.0))


def eq_zones(n: int, *, carry: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The zones of the partition of S^2 into `n` regions, north to south.

    ``carry=False`` (the default): CloudCompare's rule (collar count rounded up, each
    collar's count rounded on its own); ``carry=True``: Leopardi's (rounded to the nearest,
    rounding errors carried, the counts add up to `n`).

    Returns
    -------
    caps : (z,) float64
        The colatitude of each zone's lower boundary (the colatitude of the cap holding the
        regions of this zone and those north of it).
    counts : (z,) int64
        Regions per zone: the north cap (1), the collars, the south cap (1).  One zone (the
        sphere) for ``n = 1``; two hemispheres for ``n = 2``.
    """
    if n < 1:
        raise ValueError(f"the partition needs at least one region; got {n}")
    if n == 1:
        return np.array([math.pi]), np.array([1], dtype=np.int64)
    ideal = 4.0 * math.pi / n
    polar = _cap_colatitude(ideal)
    if n == 2:
        return np.array([polar, math.pi]), np.array([1, 1], dtype=np.int64)
    band = (math.pi - 2.0 * polar) / math.sqrt(ideal)
    collars = max(1, round(band) if carry else math.ceil(band))
    width = (math.pi - 2.0 * polar) / collars
    counts, carried = [1], 0.0
    for j in range(collars):
        top, bottom = polar + j * width, polar + (j + 1) * width
        wanted = 2.0 * math.pi * (math.cos(top) - math.cos(bottom)) / ideal
        if carry:
            whole = math.floor(wanted + carried + 0.5)
            carried += wanted - whole
        else:
            whole = max(1, round(wanted))
        counts.append(whole)
    counts.append(1)
    # rounded alone, the counts need not add up to n: the regions share the sphere
    # equally, so that the partition stays symmetric about the equator
    share = 4.0 * math.pi / sum(counts)
    caps = np.array([_cap_colatitude(k * share) for k in np.cumsum(counts)])
    caps[-1] = math.pi
    return caps, np.array(counts, dtype=np.int64)


def _leopardi_offset(above: int, below: int) -> float:
    """Leopardi's turn (a fraction of a full turn) between a collar and the one below."""
    return (1.0 / below - 1.0 / above) / 2.0 + math.gcd(above, below) / (2.0 * above * below)


def eq_centres(
    n: int, *, carry: bool = False, first_longitudes=None
) -> tuple[np.ndarray, np.ndarray]:
    """Colatitude and longitude (radians) of the direction of each region, north to south.

    Each collar's directions sit on equally spaced longitudes, the first at its entry of
    `first_longitudes` (degrees, one per collar, north to south) or, without it, at the
    middle of its first sector turned by Leopardi's cumulative offsets.  The poles are the
    caps' directions.
    """
    caps, counts = eq_zones(n, carry=carry)
    if n == 1:
        return np.zeros(1), np.zeros(1)
    colatitude, longitude = [0.0], [0.0]
    offset = 0.0
    for zone in range(1, len(counts) - 1):
        m = int(counts[zone])
        middle = 0.5 * (caps[zone - 1] + caps[zone])
        if first_longitudes is not None and zone - 1 < len(first_longitudes):
            first = math.radians(first_longitudes[zone - 1])
        else:
            first = math.pi / m + 2.0 * math.pi * offset
        colatitude.extend([middle] * m)
        longitude.extend(np.mod(first + np.arange(m) * (2.0 * math.pi / m), 2.0 * math.pi))
        offset += _leopardi_offset(m, int(counts[zone + 1]))
        offset -= math.floor(offset)
    colatitude.append(math.pi)
    longitude.append(0.0)
    return np.array(colatitude), np.array(longitude)


def light_directions(rays: int, hemisphere: bool = True) -> np.ndarray:
    """(k, 3) unit vectors towards the light, as CloudCompare's qPCV makes them (module's
    notes): the partition of `rays` regions, or with `hemisphere` the directions of
    ``2 * rays`` regions strictly north of the equator."""
    measured = QPCV_256_LONGITUDES if (rays == 256 and hemisphere) else None
    colatitude, longitude = eq_centres(2 * rays if hemisphere else rays, first_longitudes=measured)
    sine = np.sin(colatitude)
    directions = np.stack(
        [sine * np.cos(longitude), sine * np.sin(longitude), np.cos(colatitude)], axis=1
    )
    if hemisphere:
        directions = directions[directions[:, 2] > EQUATOR]
    return np.ascontiguousarray(directions)
