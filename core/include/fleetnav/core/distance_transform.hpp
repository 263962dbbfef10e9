#pragma once

namespace fleetnav {

/// One-dimensional squared Euclidean distance transform (Felzenszwalb and Huttenlocher, "Distance
/// Transforms of Sampled Functions", 2012, algorithm DT(f)): d[q] = min_p ((q − p)² + f[p]), the
/// lower envelope of parabolas rooted at f's samples, in O(n). Use a large finite f (e.g. 1e12)
/// for "no site here". Scratch: v holds n ints, z holds n + 1 doubles. Apply it along rows, then
/// columns, for the exact 2D transform. Pure function; thread-safe.
void SquaredDistanceTransform1d(const double* f, int n, double* d, int* v, double* z);

}  // namespace fleetnav
