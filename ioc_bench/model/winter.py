"""Winter's anthropometric table: the body-segment parameters every walker is scaled from.

Winter (2009), *Biomechanics and Motor Control of Human Movement*, 4th ed., Table 4.1 (after
Dempster), and the hip-to-shoulder length of Figure 4.1 (after Drillis & Contini). The
default walker (``docs/spec.md``), the subject's walker of the human track and the walkers
with feet all take their masses, centres of mass and radii of gyration from here.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class WinterSegment:
    """One row of Winter's Table 4.1.

    Attributes:
        mass: segment mass over body mass.
        com: centre of mass from the proximal end, over the segment length.
        gyration: radius of gyration about the centre of mass, over the segment length.
    """

    mass: float
    com: float
    gyration: float


#: Winter (2009) Table 4.1: HAT (greater trochanter to glenohumeral joint), thigh (greater
#: trochanter to femoral condyles), leg (femoral condyles to medial malleolus), foot
#: (lateral malleolus to head of metatarsal II).
WINTER: dict[str, WinterSegment] = {
    "hat": WinterSegment(0.678, 0.626, 0.496),
    "thigh": WinterSegment(0.100, 0.433, 0.323),
    "leg": WinterSegment(0.0465, 0.433, 0.302),
    "foot": WinterSegment(0.0145, 0.50, 0.475),
}
#: Hip (greater trochanter) to shoulder (glenohumeral joint) over body height (Winter Fig. 4.1).
HAT_LENGTH = 0.818 - 0.530
