// Rotation of real SH coefficients in shprt's basis (docs/conventions.md: Green 2003, with the
// Condon–Shortley phase, index l(l+1)+m, θ from +Z, φ from +X toward +Y), for the browser viewer.
// A line-by-line port of src/sh/rotation_ivanic.cpp:
//   J. Ivanic, K. Ruedenberg, "Rotation Matrices for Real Spherical Harmonics. Direct
//   Determination by Recursion", J. Phys. Chem. 100(15):6342–6347, 1996, Tables 1 and 2, with the
//   corrections of J. Phys. Chem. A 102(45):9099, 1998.
// The rotation of R maps the coefficients of f to those of g(d) = f(R⁻¹ d): a light feature at
// direction s appears at R·s, as `shprt render --rotate` (light/light_setup.hpp).

// R = Ry(yaw)·Rx(pitch)·Rz(roll), degrees, rows of a 3×3 matrix (core/rotation3.hpp).
export function matrixFromYawPitchRollDeg(yaw, pitch, roll) {
    const d = Math.PI / 180;
    const rx = (a) => { const c = Math.cos(a), s = Math.sin(a); return [[1, 0, 0], [0, c, -s], [0, s, c]]; };
    const ry = (a) => { const c = Math.cos(a), s = Math.sin(a); return [[c, 0, s], [0, 1, 0], [-s, 0, c]]; };
    const rz = (a) => { const c = Math.cos(a), s = Math.sin(a); return [[c, -s, 0], [s, c, 0], [0, 0, 1]]; };
    return mul3(ry(yaw * d), mul3(rx(pitch * d), rz(roll * d)));
}

function mul3(a, b) {
    const r = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (let i = 0; i < 3; ++i)
        for (let j = 0; j < 3; ++j)
            for (let k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
    return r;
}

// Band blocks D^l, l < bands, each a Float64Array of (2l+1)² entries, row m, column n.
export function shRotationBlocks(R, bands) {
    const blocks = [new Float64Array([1])];
    if (bands === 1) return blocks;
    // Band 1 in Ivanic's basis (y, z, x): D¹[m'][m] = R[p(m')][p(m)].
    const perm = [1, 2, 0];
    const b1 = new Float64Array(9);
    for (let i = 0; i < 3; ++i)
        for (let j = 0; j < 3; ++j) b1[i * 3 + j] = R[perm[i]][perm[j]];
    blocks.push(b1);
    const r1 = (m, n) => b1[(m + 1) * 3 + (n + 1)];
    for (let l = 2; l < bands; ++l) {
        const pl = l - 1, ps = 2 * pl + 1, prevData = blocks[l - 1];
        const prev = (m, n) => prevData[(m + pl) * ps + (n + pl)];
        const P = (i, a, b) => {
            if (b === l) return r1(i, 1) * prev(a, l - 1) - r1(i, -1) * prev(a, -l + 1);
            if (b === -l) return r1(i, 1) * prev(a, -l + 1) + r1(i, -1) * prev(a, l - 1);
            return r1(i, 0) * prev(a, b);
        };
        const V = (m, n) => {
            if (m === 0) return P(1, 1, n) + P(-1, -1, n);
            if (m > 0) {
                const d = m === 1 ? 1 : 0;
                let v = P(1, m - 1, n) * Math.sqrt(1 + d);
                if (m !== 1) v -= P(-1, -m + 1, n);
                return v;
            }
            const d = m === -1 ? 1 : 0;
            let v = P(-1, -m - 1, n) * Math.sqrt(1 + d);
            if (m !== -1) v += P(1, m + 1, n);
            return v;
        };
        const W = (m, n) => (m > 0 ? P(1, m + 1, n) + P(-1, -m - 1, n)
                                   : P(1, m - 1, n) - P(-1, -m + 1, n));
        const size = 2 * l + 1;
        const out = new Float64Array(size * size);
        const invDen = [], su = [], sv = [], sw = [];
        for (let k = -l; k <= l; ++k) {
            const ak = Math.abs(k), d = k === 0 ? 1 : 0;
            invDen[k + l] = 1 / Math.sqrt(ak === l ? 2 * l * (2 * l - 1) : (l + k) * (l - k));
            su[k + l] = Math.sqrt((l + k) * (l - k));
            sv[k + l] = 0.5 * Math.sqrt((1 + d) * (l + ak - 1) * (l + ak)) * (1 - 2 * d);
            sw[k + l] = -0.5 * Math.sqrt(Math.max(0, (l - ak - 1) * (l - ak))) * (1 - d);
        }
        for (let m = -l; m <= l; ++m)
            for (let n = -l; n <= l; ++n) {
                const u = su[m + l] * invDen[n + l];
                const v = sv[m + l] * invDen[n + l];
                const w = sw[m + l] * invDen[n + l];
                let value = 0;
                if (u !== 0) value += u * P(0, m, n);
                if (v !== 0) value += v * V(m, n);
                if (w !== 0) value += w * W(m, n);
                out[(m + l) * size + (n + l)] = value;
            }
        blocks.push(out);
    }
    // Ivanic's real SH carry no Condon–Shortley phase; ours do: S·D·S with S = diag((−1)^m).
    for (let l = 1; l < bands; ++l) {
        const size = 2 * l + 1, out = blocks[l];
        for (let m = -l; m <= l; ++m)
            for (let n = -l; n <= l; ++n)
                if ((m + n) & 1) out[(m + l) * size + (n + l)] = -out[(m + l) * size + (n + l)];
    }
    return blocks;
}

// Rotates `coeffs` (K = bands² values) by the blocks into a new Float64Array.
export function rotateSh(blocks, coeffs) {
    const out = new Float64Array(coeffs.length);
    for (let l = 0; l < blocks.length; ++l) {
        const size = 2 * l + 1, base = l * l, D = blocks[l];
        for (let i = 0; i < size; ++i) {
            let s = 0;
            for (let j = 0; j < size; ++j) s += D[i * size + j] * coeffs[base + j];
            out[base + i] = s;
        }
    }
    return out;
}
