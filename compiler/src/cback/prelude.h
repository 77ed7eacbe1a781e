#include <stdint.h>
#include <string.h>
#include <math.h>

/* Floating point: every IR operation is a statement of its own, so no
   compiler fuses a multiply and an add within one expression; GCC in its
   GNU modes also fuses across statements: compile with -std=c99 (or
   -ffp-contract=off), as the IEEE results of the reference need. */

typedef struct LadderMemory LadderMemory;

/* The image is addressed in bytes at the runtime's layout offsets; loads
   and stores go through memcpy (no alignment or aliasing assumptions;
   compilers turn them into plain moves). */
static inline int16_t ld_load16(const uint8_t *p) { int16_t v; memcpy(&v, p, 2); return v; }
static inline int32_t ld_load32(const uint8_t *p) { int32_t v; memcpy(&v, p, 4); return v; }
static inline void ld_store16(uint8_t *p, int16_t v) { memcpy(p, &v, 2); }
static inline void ld_store32(uint8_t *p, int32_t v) { memcpy(p, &v, 4); }

/* A run-time index, as an unsigned minimum: a negative one is huge and
   clamps too. */
static inline uint32_t ld_clamp(int32_t index, uint32_t last) {
    uint32_t u = (uint32_t)index;
    return u < last ? u : last;
}

static inline float ld_f32_bits(uint32_t bits) { float f; memcpy(&f, &bits, 4); return f; }
static inline double ld_f64_bits(uint64_t bits) { double f; memcpy(&f, &bits, 8); return f; }
static inline int32_t ld_f32_to_i32_bits(float f) { int32_t v; memcpy(&v, &f, 4); return v; }
static inline int64_t ld_f64_to_i64_bits(double f) { int64_t v; memcpy(&v, &f, 8); return v; }

/* Two's-complement integer arithmetic on N-bit values, wrapping, without
   the undefined behaviour of signed overflow in C: the arithmetic is done
   on the unsigned type A and brought back by ld_sN, which maps the
   unsigned N-bit value to the signed one without an implementation-defined
   conversion. Division by zero gives 0 and the one overflowing division
   (MIN / -1) gives MIN, where machine code would trap; the compiler never
   emits either. Shift amounts are taken modulo N, as machine shifts do. */
#define LD_INT_OPS(N, S, U, A, SMIN, SMAX)                                              \
    static inline S ld_s##N(A a) {                                                      \
        U u = (U)a;                                                                     \
        return u <= (U)SMAX ? (S)u : (S)((S)(u - (U)SMAX - 1u) + SMIN);                 \
    }                                                                                   \
    static inline S ld_add##N(S a, S b) { return ld_s##N((A)((A)a + (A)b)); }           \
    static inline S ld_sub##N(S a, S b) { return ld_s##N((A)((A)a - (A)b)); }           \
    static inline S ld_mul##N(S a, S b) { return ld_s##N((A)((A)a * (A)b)); }           \
    static inline S ld_div##N(S a, S b) {                                               \
        if (b == 0) return 0;                                                           \
        if (a == SMIN && b == -1) return SMIN;                                          \
        return (S)(a / b);                                                              \
    }                                                                                   \
    static inline S ld_rem##N(S a, S b) {                                               \
        if (b == 0 || b == -1) return 0;                                                \
        return (S)(a % b);                                                              \
    }                                                                                   \
    static inline S ld_and##N(S a, S b) { return ld_s##N((A)((A)a & (A)b)); }           \
    static inline S ld_or##N(S a, S b) { return ld_s##N((A)((A)a | (A)b)); }            \
    static inline S ld_xor##N(S a, S b) { return ld_s##N((A)((A)a ^ (A)b)); }           \
    static inline S ld_shl##N(S a, S b) {                                               \
        return ld_s##N((A)((A)(U)a << ((A)b & (N - 1))));                                \
    }                                                                                   \
    static inline S ld_ushr##N(S a, S b) {                                              \
        return ld_s##N((A)((U)a >> ((A)b & (N - 1))));                                   \
    }                                                                                   \
    static inline S ld_sshr##N(S a, S b) {                                              \
        unsigned n = (unsigned)((A)b & (N - 1));                                        \
        return a < 0 ? (S)~(S)((S)~a >> n) : (S)(a >> n);                               \
    }                                                                                   \
    static inline S ld_popcnt##N(S a) {                                                 \
        U u = (U)a;                                                                     \
        S count = 0;                                                                    \
        while (u) { count = (S)(count + (S)(u & 1u)); u = (U)(u >> 1); }                \
        return count;                                                                   \
    }                                                                                   \
    static inline S ld_clz##N(S a) {                                                    \
        U u = (U)a;                                                                     \
        S count = 0;                                                                    \
        U top = (U)((U)1 << (N - 1));                                                   \
        while (count < N && !(u & top)) { count = (S)(count + 1); u = (U)(u << 1); }    \
        return count;                                                                   \
    }                                                                                   \
    /* Float to integer, saturating: NaN is 0. */                                       \
    static inline S ld_sat##N(double x) {                                               \
        if (x != x) return 0;                                                           \
        if (x <= (double)SMIN) return SMIN;                                             \
        if (x >= -(double)SMIN) return SMAX;                                            \
        return (S)x;                                                                    \
    }                                                                                   \
    static inline S ld_isqrt##N(S a) { return ld_sat##N(sqrt((double)a)); }

LD_INT_OPS(8, int8_t, uint8_t, uint32_t, INT8_MIN, INT8_MAX)
LD_INT_OPS(16, int16_t, uint16_t, uint32_t, INT16_MIN, INT16_MAX)
LD_INT_OPS(32, int32_t, uint32_t, uint32_t, INT32_MIN, INT32_MAX)
LD_INT_OPS(64, int64_t, uint64_t, uint64_t, INT64_MIN, INT64_MAX)
