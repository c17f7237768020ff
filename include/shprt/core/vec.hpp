// Small fixed-size vectors and 3x3 matrices for host and device code. Plain aggregates: no
// constructors beyond aggregate initialisation, so they can live in CUDA constant memory and in
// arrays copied byte-for-byte to the GPU.
#pragma once

#include "shprt/core/hd.hpp"

#include <cmath>

namespace shprt {

template <class T>
struct Vec3 {
    T x, y, z;

    SHPRT_HD_INLINE T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    SHPRT_HD_INLINE T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

template <class T>
SHPRT_HD_INLINE Vec3<T> operator+(Vec3<T> a, Vec3<T> b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> operator-(Vec3<T> a, Vec3<T> b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> operator-(Vec3<T> a) {
    return {-a.x, -a.y, -a.z};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> operator*(Vec3<T> a, T s) {
    return {a.x * s, a.y * s, a.z * s};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> operator*(T s, Vec3<T> a) {
    return {a.x * s, a.y * s, a.z * s};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> operator/(Vec3<T> a, T s) {
    return {a.x / s, a.y / s, a.z / s};
}
template <class T>
SHPRT_HD_INLINE Vec3<T>& operator+=(Vec3<T>& a, Vec3<T> b) {
    a = a + b;
    return a;
}
template <class T>
SHPRT_HD_INLINE bool operator==(Vec3<T> a, Vec3<T> b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

template <class T>
SHPRT_HD_INLINE T dot(Vec3<T> a, Vec3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
SHPRT_HD_INLINE Vec3<T> cross(Vec3<T> a, Vec3<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
SHPRT_HD_INLINE T length(Vec3<T> a) {
    return std::sqrt(dot(a, a));
}
// Unit vector along `a`; `a` must be non-zero.
template <class T>
SHPRT_HD_INLINE Vec3<T> normalize(Vec3<T> a) {
    return a / length(a);
}
template <class T>
SHPRT_HD_INLINE Vec3<T> vmin(Vec3<T> a, Vec3<T> b) {
    return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <class T>
SHPRT_HD_INLINE Vec3<T> vmax(Vec3<T> a, Vec3<T> b) {
    return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
template <class U, class T>
SHPRT_HD_INLINE Vec3<U> cast(Vec3<T> a) {
    return {static_cast<U>(a.x), static_cast<U>(a.y), static_cast<U>(a.z)};
}

// Row-major 3x3 matrix: m[row][col]; acts on column vectors (v' = M v).
template <class T>
struct Mat3 {
    T m[3][3];

    SHPRT_HD_INLINE static Mat3 identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }
};

using Mat3d = Mat3<double>;
using Mat3f = Mat3<float>;

template <class T>
SHPRT_HD_INLINE Vec3<T> operator*(const Mat3<T>& a, Vec3<T> v) {
    return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
            a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
            a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}
template <class T>
SHPRT_HD_INLINE Mat3<T> operator*(const Mat3<T>& a, const Mat3<T>& b) {
    Mat3<T> r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}
template <class T>
SHPRT_HD_INLINE bool operator==(const Mat3<T>& a, const Mat3<T>& b) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a.m[i][j] != b.m[i][j]) return false;
    return true;
}
template <class T>
SHPRT_HD_INLINE Mat3<T> transpose(const Mat3<T>& a) {
    Mat3<T> r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
    return r;
}

}  // namespace shprt
