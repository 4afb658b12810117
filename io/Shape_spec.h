// Command-line shape specs and poses (docs/cli.md): `point`, `sphere:r`,
// `ellipsoid:a,b,c`, `torus:R,r`, `cylinder:r,h`, `plane:w,h`; poses `x,y,z` or
// `x,y,z,qw,qx,qy,qz`.
#pragma once

#include <string>

#include "kernel/Body.h"
#include "kernel/Rigid_pose_3.h"

namespace extremal::io {

// True when `text` names a shape kind (`point`, or a kind followed by ':'); anything else is a
// file path.
bool is_shape_spec(const std::string& text);

// The body for a shape spec. Throws Invalid_input naming the spec and the reason.
Body parse_shape_spec(const std::string& text);

// A pose from `x,y,z` or `x,y,z,qw,qx,qy,qz`. Throws Invalid_input naming the text.
Rigid_pose_3 parse_pose(const std::string& text);

}  // namespace extremal::io
