// Packed per-frame kernel of the fixed-size FilterBank: the same frame equations as
// HypothesisFilter (r = z - H x⁻, q = rᵀ A⁻¹ r, x⁺ = x⁻ + K r; x⁻ = Phi x + Bd u), on
// column-major copies of the matrices whose columns are zero-padded to a multiple of four
// rows, so every column operation is a run of 4-wide fused multiply-adds (GCC/Clang vector
// extensions compiled with target("avx2,fma")). The build stays portable (no -march): the
// kernel is compiled for AVX2/FMA as a function attribute and used only when the CPU has
// both (checked once at run time); otherwise the bank runs its Eigen path. Sums over
// columns are split into two interleaved partial sums (the kernel is latency-bound
// otherwise), so results differ from the Eigen path by rounding only (~1e-16 relative).
//
// Sizes: NX states, NU inputs, NZ measurements (compile-time); PX = NX rounded up to 4,
// PZ = NZ rounded up to 4. Everything here is noexcept and allocation-free; pointers passed
// in must hold NU (u), NZ (z) doubles and, per filter, PX (x, zero beyond NX) doubles;
// outputs PZ (r) and PX (x) doubles per filter, zero beyond NZ / NX; *probe is 0 if every
// r and x written is finite, NaN otherwise (sum of value * 0). A third kernel blends:
// x̂ = sum_k p_k x⁺_k and z_hat = H_out x̂ in one pass. PackedBank (packed_bank.h) holds a
// bank's matrices and states in this layout and calls these kernels. The kernels read filter
// f's matrices through PackedRefs refs[f] (where each one lies: filters with identical
// matrices read one copy), so which copy is read changes no arithmetic.
#pragma once

#include <cstring>

#if defined(__GNUC__) || defined(__clang__)
#define F16MMAE_PACKED_KERNEL 1
#else
#define F16MMAE_PACKED_KERNEL 0
#endif

namespace f16mmae {

constexpr bool kPackedKernel = F16MMAE_PACKED_KERNEL;

constexpr int padded4(int n) { return (n + 3) / 4 * 4; }

// The matrices one frame reads of one filter, column-major, columns padded with zeros to PX /
// PZ rows, in the order the frame reads them (update: H, A⁻¹, K; propagate: Bd), so a bank's
// filters are one contiguous run the hardware prefetchers follow. Phi is held apart
// (PackedPhi): the paper's hypotheses share one, which the bank then stores and reads once.
template <int NX, int NU, int NZ>
struct alignas(64) PackedFilter {
  static constexpr int PX = padded4(NX), PZ = padded4(NZ);
  double h[NX][PZ];      // H,   column j = H(:, j)
  double a_inv[NZ][PZ];  // A⁻¹, column j
  double k[NZ][PX];      // K,   column j
  double bd[NU][PX];     // Bd,  column j

  // From a HypothesisFilter (its model and A⁻¹).
  template <class Hypothesis>
  void load(const Hypothesis& f) noexcept {
    std::memset(this, 0, sizeof(*this));
    const auto& m = f.model();
    for (int j = 0; j < NX; ++j)
      for (int i = 0; i < NZ; ++i) h[j][i] = m.h(i, j);
    for (int j = 0; j < NZ; ++j)
      for (int i = 0; i < NZ; ++i) a_inv[j][i] = f.a_inverse()(i, j);
    for (int j = 0; j < NZ; ++j)
      for (int i = 0; i < NX; ++i) k[j][i] = m.k(i, j);
    for (int j = 0; j < NU; ++j)
      for (int i = 0; i < NX; ++i) bd[j][i] = m.bd(i, j);
  }
};

// Where the kernels read one filter's matrices (each in the PackedFilter layout: H and A⁻¹
// columns of PZ rows, K and Bd columns of PX rows): its own PackedFilter's arrays, or another
// filter's that hold the same values bit for bit (PackedBank::link).
struct PackedRefs {
  const double* h = nullptr;
  const double* a_inv = nullptr;
  const double* k = nullptr;
  const double* bd = nullptr;
};

// One filter's Phi in the same layout (column j = Phi(:, j), PX rows).
template <int NX>
struct alignas(64) PackedPhi {
  static constexpr int PX = padded4(NX);
  double phi[NX][PX];

  template <class Hypothesis>
  void load(const Hypothesis& f) noexcept {
    std::memset(this, 0, sizeof(*this));
    for (int j = 0; j < NX; ++j)
      for (int i = 0; i < NX; ++i) phi[j][i] = f.model().phi(i, j);
  }
};

#if F16MMAE_PACKED_KERNEL
namespace packed {

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

typedef double v4d __attribute__((vector_size(32)));
// The same, for loads and stores at any 8-byte-aligned address (may alias double).
typedef double v4du __attribute__((vector_size(32), aligned(8), may_alias));
// Macros, not functions: a function taking or returning a 32-byte vector changes the ABI
// between the two targets (GCC's -Wpsabi), an expression does not.
#define F16MMAE_LD(ptr) (*reinterpret_cast<const v4du*>(ptr))
#define F16MMAE_ST(ptr, v) (*reinterpret_cast<v4du*>(ptr) = (v))
#define F16MMAE_SPLAT(x) (v4d{} + (x))

// One frame's update for K filters: r_k, q_k, candidate x⁺_k (see the header comment).
// Every sum over columns runs in two interleaved partial sums (even / odd columns) so the
// multiply-add chains are half as long: the kernel is latency-bound otherwise.
#define F16MMAE_UPDATE_BODY                                                                  \
  constexpr int PX = P::PX, PZ = P::PZ, BX = PX / 4, BZ = PZ / 4;                            \
  alignas(32) double zp[PZ] = {};                                                            \
  for (int i = 0; i < NZ; ++i) zp[i] = z[i];                                                 \
  v4d probe_r = {}, probe_x = {};                                                            \
  for (int f = 0; f < K; ++f) {                                                              \
    const PackedRefs& p = refs[f];                                                           \
    const double* x = x_prior[f];                                                            \
    v4d r0[BZ], r1[BZ] = {};                                                                 \
    _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) r0[b] = F16MMAE_LD(zp + 4 * b);          \
    _Pragma("GCC unroll 16") for (int j = 0; j + 1 < NX; j += 2) {                           \
      const v4d x0 = F16MMAE_SPLAT(x[j]), x1 = F16MMAE_SPLAT(x[j + 1]);                                      \
      _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) {                                 \
        r0[b] -= F16MMAE_LD(p.h + j * PZ + 4 * b) * x0;                                                 \
        r1[b] -= F16MMAE_LD(p.h + (j + 1) * PZ + 4 * b) * x1;                                             \
      }                                                                                      \
    }                                                                                        \
    if (NX % 2) {                                                                            \
      const v4d xl = F16MMAE_SPLAT(x[NX - 1]);                                                       \
      _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) r0[b] -= F16MMAE_LD(p.h + (NX - 1) * PZ + 4 * b) * xl; \
    }                                                                                        \
    double* rr = r_out + f * PZ;                                                             \
    v4d r[BZ];                                                                               \
    _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) {                                   \
      r[b] = r0[b] + r1[b];                                                                  \
      F16MMAE_ST(rr + 4 * b, r[b]);                                                              \
      probe_r += r[b] * 0.0;                                                                 \
    }                                                                                        \
    v4d s0[BZ] = {}, s1[BZ] = {};                                                            \
    v4d xp0[BX], xp1[BX] = {};                                                               \
    double* xo = x_out + f * PX;                                                             \
    _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) xp0[b] = F16MMAE_LD(x + 4 * b);          \
    _Pragma("GCC unroll 8") for (int j = 0; j + 1 < NZ; j += 2) {                            \
      const v4d a0 = F16MMAE_SPLAT(r[j / 4][j % 4]), a1 = F16MMAE_SPLAT(r[(j + 1) / 4][(j + 1) % 4]);                                    \
      _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) {                                 \
        s0[b] += F16MMAE_LD(p.a_inv + j * PZ + 4 * b) * a0;                                             \
        s1[b] += F16MMAE_LD(p.a_inv + (j + 1) * PZ + 4 * b) * a1;                                         \
      }                                                                                      \
      _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                 \
        xp0[b] += F16MMAE_LD(p.k + j * PX + 4 * b) * a0;                                                \
        xp1[b] += F16MMAE_LD(p.k + (j + 1) * PX + 4 * b) * a1;                                            \
      }                                                                                      \
    }                                                                                        \
    if (NZ % 2) {                                                                            \
      const v4d al = F16MMAE_SPLAT(r[(NZ - 1) / 4][(NZ - 1) % 4]);                                                      \
      _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) s0[b] += F16MMAE_LD(p.a_inv + (NZ - 1) * PZ + 4 * b) * al; \
      _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) xp0[b] += F16MMAE_LD(p.k + (NZ - 1) * PX + 4 * b) * al; \
    }                                                                                        \
    v4d qv = r[0] * (s0[0] + s1[0]);                                                         \
    _Pragma("GCC unroll 8") for (int b = 1; b < BZ; ++b) qv += r[b] * (s0[b] + s1[b]);       \
    q_out[f] = (qv[0] + qv[1]) + (qv[2] + qv[3]);                                            \
    _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                   \
      const v4d xn = xp0[b] + xp1[b];                                                        \
      F16MMAE_ST(xo + 4 * b, xn);                                                            \
      probe_x += xn * 0.0;                                                                   \
    }                                                                                        \
  }                                                                                          \
  const v4d pr = probe_r + probe_x;                                                          \
  *probe = (pr[0] + pr[1]) + (pr[2] + pr[3]);

// One frame's propagation for K filters: x_out_k = Phi x_k + Bd u (two partial sums).
// Filter f's Phi columns start at phi + f * phi_stride (stride 0: one Phi shared by all;
// PackedPhi layout).
#define F16MMAE_PROPAGATE_BODY                                                               \
  constexpr int PX = P::PX, BX = PX / 4;                                                     \
  v4d probe_x = {};                                                                          \
  for (int f = 0; f < K; ++f) {                                                              \
    const PackedRefs& p = refs[f];                                                           \
    const double* ph = phi + f * phi_stride;                                                 \
    const double* x = x_in[f];                                                               \
    v4d y0[BX] = {}, y1[BX] = {};                                                            \
    _Pragma("GCC unroll 16") for (int j = 0; j + 1 < NX; j += 2) {                           \
      const v4d x0 = F16MMAE_SPLAT(x[j]), x1 = F16MMAE_SPLAT(x[j + 1]);                                      \
      _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                 \
        y0[b] += F16MMAE_LD(ph + j * PX + 4 * b) * x0;                                         \
        y1[b] += F16MMAE_LD(ph + (j + 1) * PX + 4 * b) * x1;                                   \
      }                                                                                      \
    }                                                                                        \
    if (NX % 2) {                                                                            \
      const v4d xl = F16MMAE_SPLAT(x[NX - 1]);                                                       \
      _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) y0[b] += F16MMAE_LD(ph + (NX - 1) * PX + 4 * b) * xl; \
    }                                                                                        \
    _Pragma("GCC unroll 8") for (int j = 0; j < NU; ++j) {                                   \
      const v4d uj = F16MMAE_SPLAT(u[j]);                                                            \
      _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                 \
        if (j % 2) y1[b] += F16MMAE_LD(p.bd + j * PX + 4 * b) * uj;                                     \
        else y0[b] += F16MMAE_LD(p.bd + j * PX + 4 * b) * uj;                                           \
      }                                                                                      \
    }                                                                                        \
    double* xo = x_out + f * PX;                                                             \
    _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                   \
      const v4d xn = y0[b] + y1[b];                                                          \
      F16MMAE_ST(xo + 4 * b, xn);                                                            \
      probe_x += xn * 0.0;                                                                   \
    }                                                                                        \
  }                                                                                          \
  *probe = (probe_x[0] + probe_x[1]) + (probe_x[2] + probe_x[3]);

// The blend of one frame: x̂ = sum_k p_k x⁺_k (x: K padded states), z_hat = H_out x̂ (h_out:
// NX columns of PZ rows). Outputs PX (x̂) and PZ (z_hat) doubles.
#define F16MMAE_BLEND_BODY                                                                   \
  constexpr int PX = P::PX, PZ = P::PZ, BX = PX / 4, BZ = PZ / 4;                            \
  v4d s0[BX] = {}, s1[BX] = {};                                                              \
  _Pragma("GCC unroll 16") for (int f = 0; f + 1 < K; f += 2) {                              \
    const v4d p0 = F16MMAE_SPLAT(p[f]), p1 = F16MMAE_SPLAT(p[f + 1]);                        \
    _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                   \
      s0[b] += F16MMAE_LD(x + f * PX + 4 * b) * p0;                                          \
      s1[b] += F16MMAE_LD(x + (f + 1) * PX + 4 * b) * p1;                                    \
    }                                                                                        \
  }                                                                                          \
  if (K % 2) {                                                                               \
    const v4d pl = F16MMAE_SPLAT(p[K - 1]);                                                  \
    _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) s0[b] += F16MMAE_LD(x + (K - 1) * PX + 4 * b) * pl; \
  }                                                                                          \
  v4d xb[BX];                                                                                \
  _Pragma("GCC unroll 8") for (int b = 0; b < BX; ++b) {                                     \
    xb[b] = s0[b] + s1[b];                                                                   \
    F16MMAE_ST(x_blend + 4 * b, xb[b]);                                                      \
  }                                                                                          \
  v4d z0[BZ] = {}, z1[BZ] = {};                                                              \
  _Pragma("GCC unroll 16") for (int j = 0; j + 1 < NX; j += 2) {                             \
    const v4d x0 = F16MMAE_SPLAT(xb[j / 4][j % 4]), x1 = F16MMAE_SPLAT(xb[(j + 1) / 4][(j + 1) % 4]); \
    _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) {                                   \
      z0[b] += F16MMAE_LD(h_out + j * PZ + 4 * b) * x0;                                      \
      z1[b] += F16MMAE_LD(h_out + (j + 1) * PZ + 4 * b) * x1;                                \
    }                                                                                        \
  }                                                                                          \
  if (NX % 2) {                                                                              \
    const v4d xl = F16MMAE_SPLAT(xb[(NX - 1) / 4][(NX - 1) % 4]);                            \
    _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) z0[b] += F16MMAE_LD(h_out + (NX - 1) * PZ + 4 * b) * xl; \
  }                                                                                          \
  _Pragma("GCC unroll 8") for (int b = 0; b < BZ; ++b) F16MMAE_ST(z_hat + 4 * b, z0[b] + z1[b]);

#if defined(__x86_64__) || defined(__i386__)
template <int K, int NX, int NU, int NZ, class P = PackedFilter<NX, NU, NZ>>
__attribute__((target("avx2,fma"))) void blend_avx2(const double* p, const double* x, const double* h_out,
                                                    double* x_blend, double* z_hat) noexcept {
  F16MMAE_BLEND_BODY
}
template <int K, int NX, int NU, int NZ, class P = PackedFilter<NX, NU, NZ>>
__attribute__((target("avx2,fma"))) void update_avx2(const PackedRefs* refs, const double* z, const double* const* x_prior,
                                                     double* r_out, double* q_out, double* x_out,
                                                     double* probe) noexcept {
  F16MMAE_UPDATE_BODY
}
template <int K, int NX, int NU, int NZ, class P = PackedFilter<NX, NU, NZ>>
__attribute__((target("avx2,fma"))) void propagate_avx2(const PackedRefs* refs, const double* phi, long phi_stride,
                                                        const double* u, const double* const* x_in,
                                                        double* x_out, double* probe) noexcept {
  F16MMAE_PROPAGATE_BODY
}
inline bool cpu_has_avx2_fma() noexcept {
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return has;
}
#else
inline bool cpu_has_avx2_fma() noexcept { return false; }
#endif

#undef F16MMAE_UPDATE_BODY
#undef F16MMAE_PROPAGATE_BODY
#undef F16MMAE_BLEND_BODY
#undef F16MMAE_LD
#undef F16MMAE_ST
#undef F16MMAE_SPLAT
#pragma GCC diagnostic pop

// The kernels the bank calls when available() (a CPU with AVX2 and FMA), else nullptr.
template <int K, int NX, int NU, int NZ>
struct Kernels {
  using P = PackedFilter<NX, NU, NZ>;
  using Update = void (*)(const PackedRefs*, const double*, const double* const*, double*, double*, double*,
                          double*) noexcept;
  using Propagate = void (*)(const PackedRefs*, const double*, long, const double*, const double* const*, double*,
                             double*) noexcept;
  using Blend = void (*)(const double*, const double*, const double*, double*, double*) noexcept;
  static bool available() noexcept { return cpu_has_avx2_fma(); }
  static Blend blend() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    if (cpu_has_avx2_fma()) return &blend_avx2<K, NX, NU, NZ>;
#endif
    return nullptr;
  }
  static Update update() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    if (cpu_has_avx2_fma()) return &update_avx2<K, NX, NU, NZ>;
#endif
    return nullptr;
  }
  static Propagate propagate() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    if (cpu_has_avx2_fma()) return &propagate_avx2<K, NX, NU, NZ>;
#endif
    return nullptr;
  }
};

}  // namespace packed
#endif

}  // namespace f16mmae
