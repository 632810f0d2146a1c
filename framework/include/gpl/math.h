// The engine's math types, defined once. Eigen (Debian libeigen3-dev) does the linear algebra.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <sstream>
#include <string>

namespace gpl {

using Vec3 = Eigen::Vector3d;     ///< a point or direction in 3D (metres, m/s, ... as named)
using Mat3 = Eigen::Matrix3d;     ///< 3x3 matrix: inertia tensors, rotations
using Quat = Eigen::Quaterniond;  ///< unit quaternion: body-to-world rotation

/// True when every component is a finite number (no NaN, no infinity).
inline bool isFinite(const Vec3& v) { return v.allFinite(); }

/// A number as people write it in messages: 0.01, 1e-06, nan (std::to_string would give 0.010000).
inline std::string formatNumber(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

}  // namespace gpl
