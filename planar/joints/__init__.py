"""Joint types. Each class supplies residual rows, Jacobian blocks and gamma, batched, and its
file form and drawing part; :data:`JOINT_TYPES` registers them (adding a joint type is one
module and one entry there), and :data:`FILE_TYPES` is what files read from them.

>>> from planar.joints import FILE_TYPES, JOINT_TYPES
>>> sorted(cls.__name__ for cls in JOINT_TYPES)[:3]
['AngleDriver', 'CarrierGear', 'CoordinateDriver']
>>> list(FILE_TYPES)
['revolute', 'prismatic', 'slot', 'gear', 'rack_pinion', 'rolling']
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

# a file entry's "type" -> {field: (field kind, required)}: the file form of every joint type
FILE_TYPES = {t: fields for cls in JOINT_TYPES for t, fields in cls.file_types.items()}

__all__ = ["FILE_TYPES", "Joint", "JOINT_TYPES"] + [cls.__name__ for cls in JOINT_TYPES]
