"""Joint types. Each class supplies residual rows, Jacobian blocks and gamma, batched.

>>> from planar.joints import JOINT_TYPES
>>> sorted(cls.__name__ for cls in JOINT_TYPES)[:3]
['AngleDriver', 'CarrierGear', 'CoordinateDriver']
"""

from planar.joints.base import Joint
from planar.joints.driver import AngleDriver, CoordinateDriver, TravelDriver
from planar.joints.gear import CarrierGear, Gear, RollingContact
from planar.joints.prismatic import Prismatic, Slot
from planar.joints.rack import RackPinion
from planar.joints.revolute import Revolute

JOINT_TYPES = (
    Revolute, Prismatic, Slot, CarrierGear, Gear, RollingContact, RackPinion,
    AngleDriver, TravelDriver, CoordinateDriver,
)

__all__ = ["Joint", "JOINT_TYPES"] + [cls.__name__ for cls in JOINT_TYPES]
