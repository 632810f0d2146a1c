// The cloth study's bare XPBD sweeps (cloth_study.h): in the instructors' tree only. Written out,
// they are a model answer of worksheet 8's solveDistanceConstraint(), and a student release
// (tools/release.py) and the Gradescope bundle leave this folder out; bench/CMakeLists.txt builds it
// where it exists.
#include <cmath>

#include "cloth_study.h"

namespace gpl::study {

void bareXpbdSweeps(std::vector<Vec3>& p, const std::vector<double>& w, std::vector<DistanceLink>& links, double h,
                    int iterations) {
    for (DistanceLink& link : links) link.lambda = 0.0;
    for (int sweep = 0; sweep < iterations; ++sweep) {
        for (DistanceLink& link : links) {
            Vec3& x1 = p[link.i];
            Vec3& x2 = p[link.j];
            const double w1 = w[link.i], w2 = w[link.j];
            // The reference hook's arithmetic, in its order: the same moves to the bit.
            const Vec3 d = x1 - x2;
            const double length = d.norm();
            const double alphaTilde = link.compliance / (h * h);
            const double denominator = w1 + w2 + alphaTilde;
            if (length == 0.0 || denominator == 0.0) continue;
            const Vec3 n = d / length;
            const double C = length - link.rest;
            const double dlambda = (-C - alphaTilde * link.lambda) / denominator;
            x1 += w1 * dlambda * n;
            x2 += -w2 * dlambda * n;
            link.lambda += dlambda;
        }
    }
}

}  // namespace gpl::study
