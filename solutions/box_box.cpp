// Worksheet 5, assignment 4: box against box, by separating axes.
//
// Inputs:  a, b         two boxes: position of the centre (m, world frame), orientation (unit
//                       quaternion, box frame to world frame), halfExtents (m, > 0, box axes)
// Outputs: no contact (std::nullopt) when some axis separates the boxes or they only touch (their
//          shadows on some axis overlap by 0 or less); otherwise a contact along the axis of least
//          overlap among the 15 candidates (the 3 + 3 face normals, the 9 cross products of an edge
//          of a with an edge of b; a face axis is kept unless an edge axis overlaps clearly less)
//            normal     that axis as a unit vector from a towards b
//            depth      the overlap of the two shadows on it (m), > 0
//            points     face axis: the face of the other box that faces the axis's face (the
//                       reference face), cut to the sides of the reference face, its corners and
//                       cuts that lie behind the reference face, each moved halfway to it; at most
//                       four (the deepest and three that span the rest). Edge axis: one point
//                       halfway between the closest points of the two edges.
//            pointCount 1..4
// The framework fills in the indices of the bodies and the restitution.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

// BEGIN SOLUTION
namespace {

// Edge axes of edges closer to parallel than this (the sine of their angle) say nothing new: a face
// axis is as good, and the cross product's direction would be mostly rounding.
constexpr double kParallel = 1e-6;
// An edge axis wins only when it overlaps less than this fraction of the best face axis: resting
// boxes then keep their face contacts instead of switching to an edge that overlaps about as much.
constexpr double kFacePreference = 0.95;

struct OrientedBox {
    Vec3 centre;  // m, world frame
    Mat3 axes;    // columns: the box's axes in the world frame
    Vec3 half;    // half extents (m)
};

OrientedBox orientedBox(const Body& b) { return {b.position, b.orientation.toRotationMatrix(), b.halfExtents}; }

double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }

// A convex polygon of at most 8 corners: a face (4) cut by four planes (one more corner each).
struct Polygon {
    std::array<Vec3, 8> corners;
    int count = 0;
};

// The face of `box` that faces against the unit direction `outward`, corners in order around it.
Polygon facingFace(const OrientedBox& box, const Vec3& outward) {
    const Vec3 along = box.axes.transpose() * outward;
    int k = 0;  // the axis closest to outward
    along.cwiseAbs().maxCoeff(&k);
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    const Vec3 centre = box.centre - sign(along[k]) * box.half[k] * box.axes.col(k);
    const Vec3 du = box.half[u] * box.axes.col(u), dv = box.half[v] * box.axes.col(v);
    return {{centre + du + dv, centre - du + dv, centre - du - dv, centre + du - dv}, 4};
}

// The part of the polygon where normal . x <= offset (one step of Sutherland-Hodgman clipping).
Polygon clip(const Polygon& in, const Vec3& normal, double offset) {
    // Each corner's height over the cutting plane, once (m; > 0: on the side cut away).
    std::array<double, 8> height;
    bool cut = false;
    for (int i = 0; i < in.count; ++i) {
        height[i] = normal.dot(in.corners[i]) - offset;
        cut |= height[i] > 0.0;
    }
    if (!cut) return in;  // nothing beyond the plane
    Polygon out;
    for (int i = 0; i < in.count; ++i) {
        const int next = i + 1 < in.count ? i + 1 : 0;
        const Vec3& p = in.corners[i];
        const Vec3& q = in.corners[next];
        const double dp = height[i], dq = height[next];
        if (dp <= 0.0) out.corners[out.count++] = p;
        if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) out.corners[out.count++] = p + dp / (dp - dq) * (q - p);
    }
    return out;
}

// Contact points of a face axis: `reference` owns the face whose outward normal is `outward` (a
// unit axis of it, index k); the facing face of `incident` is cut to the reference face's sides.
Contact faceContact(const OrientedBox& reference, const OrientedBox& incident, int k, const Vec3& outward) {
    Polygon face = facingFace(incident, outward);
    for (int side = 1; side <= 2; ++side) {
        const Vec3 axis = reference.axes.col((k + side) % 3);
        const double centre = axis.dot(reference.centre), half = reference.half[(k + side) % 3];
        face = clip(face, axis, centre + half);
        face = clip(face, -axis, -centre + half);
    }
    const double faceOffset = outward.dot(reference.centre) + reference.half[k];
    // The corners behind the reference face, with their heights above it (m, < 0).
    std::array<Vec3, 8> behind;
    std::array<double, 8> height;
    int count = 0;
    for (int i = 0; i < face.count; ++i) {
        const double s = outward.dot(face.corners[i]) - faceOffset;
        if (s < 0.0) {
            behind[count] = face.corners[i] - 0.5 * s * outward;  // halfway to the reference face
            height[count++] = s;
        }
    }
    Contact c;
    if (count == 0) {  // rounding at a grazing contact: the incident face's centre stands for it
        Vec3 middle = Vec3::Zero();
        for (int i = 0; i < face.count; ++i) middle += face.corners[i] / face.count;
        c.points[0] = face.count > 0 ? middle : Vec3(incident.centre);
        c.pointCount = 1;
        return c;
    }
    if (count <= kMaxContactPoints) {
        for (int i = 0; i < count; ++i) c.points[i] = behind[i];
        c.pointCount = count;
        return c;
    }
    // Four of them: the deepest, the one farthest from it, the one farthest from the line through
    // those two, and the one farthest on the line's other side (or, when none is there, the one
    // farthest from the three).
    std::array<int, 4> pick{0, 0, 0, 0};
    for (int i = 1; i < count; ++i) {
        if (height[i] < height[pick[0]]) pick[0] = i;
    }
    const Vec3 p0 = behind[pick[0]];
    for (int i = 0; i < count; ++i) {
        if ((behind[i] - p0).squaredNorm() > (behind[pick[1]] - p0).squaredNorm()) pick[1] = i;
    }
    const Vec3 line = behind[pick[1]] - p0;
    const auto area = [&](int i) { return line.cross(behind[i] - p0).dot(outward); };  // signed, twice
    for (int i = 0; i < count; ++i) {
        if (std::abs(area(i)) > std::abs(area(pick[2]))) pick[2] = i;
    }
    const double side = area(pick[2]) < 0.0 ? -1.0 : 1.0;
    const auto spread = [&](int i) {
        return std::min({(behind[i] - p0).squaredNorm(), (behind[i] - behind[pick[1]]).squaredNorm(),
                         (behind[i] - behind[pick[2]]).squaredNorm()});
    };
    pick[3] = pick[0];
    for (int i = 0; i < count; ++i) {
        if (-side * area(i) > -side * area(pick[3])) pick[3] = i;
    }
    if (pick[3] == pick[0]) {
        for (int i = 0; i < count; ++i) {
            if (spread(i) > spread(pick[3])) pick[3] = i;
        }
    }
    for (int p = 0; p < 4; ++p) {  // each once
        if (std::find(pick.begin(), pick.begin() + p, pick[p]) == pick.begin() + p) c.points[c.pointCount++] = behind[pick[p]];
    }
    return c;
}

// Contact point of an edge axis (unit, from a towards b) between edge i of a and edge j of b:
// halfway between the closest points of the edge of a nearest b and the edge of b nearest a.
Vec3 edgePoint(const OrientedBox& a, int i, const OrientedBox& b, int j, const Vec3& normal) {
    Vec3 pa = a.centre, pb = b.centre;
    for (int m = 0; m < 3; ++m) {  // the other two axes of each
        if (m != i) pa += sign(normal.dot(a.axes.col(m))) * a.half[m] * a.axes.col(m);
        if (m != j) pb -= sign(normal.dot(b.axes.col(m))) * b.half[m] * b.axes.col(m);
    }
    const Vec3 da = a.axes.col(i), db = b.axes.col(j), r = pa - pb;
    const double cosine = da.dot(db), c = da.dot(r), f = db.dot(r);
    const double denominator = 1.0 - cosine * cosine;  // > 0: the edges are not parallel
    const double s = std::clamp((cosine * f - c) / denominator, -a.half[i], a.half[i]);
    const double t = std::clamp((f - cosine * c) / denominator, -b.half[j], b.half[j]);
    return 0.5 * (pa + s * da + pb + t * db);
}

}  // namespace
// ELSE STUB
// // Helpers of your own may go here, in an anonymous namespace: namespace { ... }
// END SOLUTION

std::optional<Contact> boxBox([[maybe_unused]] const Body& a, [[maybe_unused]] const Body& b) {
    // BEGIN SOLUTION
    const Vec3 d = b.position - a.position;

    // (6) of the worksheet: the fifteen overlaps (5) from the nine cosines C_ij = a_i . b_j, in a's
    // frame. There a's axes are the unit vectors, b's axis j is column j of C = A^T B (the matrix
    // of q_a^-1 q_b), and the centres are t = A^T (c_b - c_a) apart.
    const Quat toA = a.orientation.conjugate();  // world frame to a's frame
    const Mat3 C = (toA * b.orientation).toRotationMatrix();
    const Mat3 absC = C.cwiseAbs();
    const Vec3 t = toA * d;
    const Vec3 &ha = a.halfExtents, &hb = b.halfExtents;

    // Face axes a_m and b_m: o = rho_a + rho_b - |L . (c_b - c_a)| (m); o <= 0: L separates them.
    double faceDepth = INFINITY;
    int face = 0;  // 0..2: a face axis of a, 3..5: of b
    for (int k = 0; k < 6; ++k) {
        const bool axisOfA = k < 3;
        const int m = k % 3;
        const double rhoA = axisOfA ? ha[m] : ha.dot(absC.col(m));
        const double rhoB = axisOfA ? hb.dot(absC.row(m).transpose()) : hb[m];
        const double apart = std::abs(axisOfA ? t[m] : C.col(m).dot(t));
        const double o = rhoA + rhoB - apart;
        if (o <= 0.0) return std::nullopt;
        if (o < faceDepth) {
            faceDepth = o;
            face = k;
        }
    }
    // Edge axes a_i x b_j, with (i, i1, i2) and (j, j1, j2) in cyclic order, each divided by its
    // length s (the sine of the edges' angle) to make it a unit axis.
    double edgeDepth = INFINITY;
    int edgeA = 0, edgeB = 0;
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            const double s = std::sqrt(C(i1, j) * C(i1, j) + C(i2, j) * C(i2, j));
            if (s < kParallel) continue;
            const double rhoA = ha[i1] * absC(i2, j) + ha[i2] * absC(i1, j);
            const double rhoB = hb[j1] * absC(i, j2) + hb[j2] * absC(i, j1);
            const double apart = std::abs(t[i2] * C(i1, j) - t[i1] * C(i2, j));
            const double o = (rhoA + rhoB - apart) / s;
            if (o <= 0.0) return std::nullopt;
            if (o < edgeDepth) {
                edgeDepth = o;
                edgeA = i;
                edgeB = j;
            }
        }
    }

    // The boxes overlap: their axes in the world frame for the contact.
    const OrientedBox boxA = orientedBox(a), boxB = orientedBox(b);
    if (edgeDepth < kFacePreference * faceDepth) {
        const Vec3 edgeAxis = boxA.axes.col(edgeA).cross(boxB.axes.col(edgeB)).normalized();
        const Vec3 normal = edgeAxis.dot(d) < 0.0 ? Vec3(-edgeAxis) : edgeAxis;
        return Contact::at(edgePoint(boxA, edgeA, boxB, edgeB, normal), normal, edgeDepth);
    }
    const bool ofA = face < 3;
    const int k = face % 3;
    Vec3 normal = (ofA ? boxA : boxB).axes.col(k);
    if (normal.dot(d) < 0.0) normal = -normal;
    // The reference face is the one of the axis's box that faces the other box.
    Contact c = ofA ? faceContact(boxA, boxB, k, normal) : faceContact(boxB, boxA, k, -normal);
    c.normal = normal;
    c.depth = faceDepth;
    return c;
    // ELSE STUB
    // kernelNotImplemented("boxBox()");
    // return std::nullopt;
    // END SOLUTION
}

}  // namespace gpl
