// The help of the model import flags that `mbstream submit` and `mbstream simulate` share.
#pragma once

namespace mbstream::cli {

inline constexpr char kRepairHelp[] =
    "repair the defects published URDFs commonly carry (each one a warning)";
inline constexpr char kCoupleMimicHelp[] =
    "hold each URDF joint with a <mimic> to its leader (q = multiplier * q(leader) + offset, "
    "run as a closed loop); without it such a joint moves freely, with a warning";

inline constexpr char kFloatingBaseHelp[] =
    "a URDF's root link moves freely (a free joint named after it: x y z qw qx qy qz, then 6 "
    "velocities) instead of being bolted to the world; a 'floating' joint to the world does "
    "the same in the file";

}  // namespace mbstream::cli
