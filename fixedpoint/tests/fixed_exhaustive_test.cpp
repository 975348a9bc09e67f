// Exhaustive checks of small formats against a plain reference: values are
// computed as long doubles (exact at these sizes) and quantised with
// floor/compare arithmetic written independently of the library.
#include <gtest/gtest.h>

#include <cmath>
#include <compare>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>

#include "fixedpoint/fixed.hpp"

namespace ceilnav::fp {
namespace {

// ---- reference ------------------------------------------------------------

struct Shape {
  int width;
  int frac;
  bool is_signed;
};

template <FixedPoint T>
constexpr Shape shape_of() {
  return {T::width, T::frac, T::is_signed};
}

std::int64_t ref_min(const Shape& s) {
  return s.is_signed ? -(std::int64_t{1} << (s.width - 1)) : 0;
}
std::int64_t ref_max(const Shape& s) {
  return s.is_signed ? (std::int64_t{1} << (s.width - 1)) - 1 : (std::int64_t{1} << s.width) - 1;
}

long double value_of(std::int64_t raw, int frac) {
  return std::ldexp(static_cast<long double>(raw), -frac);
}

// Raw word the value x must become in shape s under the given modes.
std::int64_t ref_quantise(long double x, const Shape& s, Rounding rounding, Overflow overflow) {
  const long double scaled = std::ldexp(x, s.frac);  // exact: a power-of-two scale
  const long double below = std::floor(scaled);
  const long double excess = scaled - below;  // in [0, 1)
  long double n = below;
  switch (rounding) {
    case Rounding::truncate:
      break;
    case Rounding::half_up:
      if (excess >= 0.5L) n = below + 1;
      break;
    case Rounding::convergent:
      if (excess > 0.5L || (excess == 0.5L && std::fmod(below, 2.0L) != 0)) n = below + 1;
      break;
  }
  const auto k = static_cast<std::int64_t>(n);
  const std::int64_t lo = ref_min(s);
  const std::int64_t hi = ref_max(s);
  if (overflow == Overflow::saturate) return k < lo ? lo : (k > hi ? hi : k);
  const std::int64_t span = std::int64_t{1} << s.width;
  return ((k - lo) % span + span) % span + lo;
}

const char* name(Rounding r) {
  switch (r) {
    case Rounding::truncate:
      return "truncate";
    case Rounding::half_up:
      return "half_up";
    case Rounding::convergent:
      return "convergent";
  }
  return "?";
}
const char* name(Overflow o) {
  return o == Overflow::wrap ? "wrap" : "saturate";
}

// A format with its modes, for failure messages.
struct TypeInfo {
  Shape shape;
  Rounding rounding;
  Overflow overflow;
};

template <FixedPoint T>
constexpr TypeInfo info_of() {
  return {shape_of<T>(), T::rounding, T::overflow};
}

std::string describe(const TypeInfo& t) {
  std::ostringstream os;
  os << (t.shape.is_signed ? "Fixed<" : "UFixed<") << t.shape.width << "," << t.shape.frac << ","
     << name(t.rounding) << "," << name(t.overflow) << ">";
  return os.str();
}

// One failed check: operation, operand(s) and results.
struct Failure {
  const char* what;
  TypeInfo a;
  std::int64_t raw_a;
  const TypeInfo* b;  // null for unary checks
  std::int64_t raw_b;
  long double got;
  long double want;
};

std::string describe(const Failure& f) {
  std::ostringstream os;
  os << f.what << ": " << describe(f.a) << " raw " << f.raw_a;
  if (f.b != nullptr) os << " with " << describe(*f.b) << " raw " << f.raw_b;
  os << ": got " << static_cast<double>(f.got) << " want " << static_cast<double>(f.want);
  return os.str();
}

// Counts checks and keeps the first failure's description.
struct Tally {
  long checks = 0;
  long failures = 0;
  std::string first_failure;

  void check(const Failure& f) {
    ++checks;
    if (f.got == f.want) return;
    if (failures++ == 0) first_failure = describe(f);
  }
};

#define EXPECT_TALLY_CLEAN(tally)                                           \
  do {                                                                      \
    std::printf("%ld checks\n", (tally).checks);                            \
    EXPECT_GT((tally).checks, 0);                                           \
    EXPECT_EQ((tally).failures, 0)                                          \
        << "of " << (tally).checks << "; first: " << (tally).first_failure; \
  } while (false)

// ---- type lists -------------------------------------------------------------

template <class... Ts>
struct TypeList {};

template <class... Lists>
struct Concat;
template <class... Ts>
struct Concat<TypeList<Ts...>> {
  using type = TypeList<Ts...>;
};
template <class... As, class... Bs, class... Rest>
struct Concat<TypeList<As...>, TypeList<Bs...>, Rest...> {
  using type = typename Concat<TypeList<As..., Bs...>, Rest...>::type;
};

// Widths Ws at one Frac, both signednesses, default modes.
template <int F, int... Ws>
using BothSigns = TypeList<Fixed<Ws, F, true>..., Fixed<Ws, F, false>...>;

template <FixedPoint T>
using AllModes =
    TypeList<typename T::template with_modes<Rounding::truncate, Overflow::wrap>,
             typename T::template with_modes<Rounding::half_up, Overflow::wrap>,
             typename T::template with_modes<Rounding::convergent, Overflow::wrap>,
             typename T::template with_modes<Rounding::truncate, Overflow::saturate>,
             typename T::template with_modes<Rounding::half_up, Overflow::saturate>,
             typename T::template with_modes<Rounding::convergent, Overflow::saturate>>;

template <class List>
struct AllModesOf;
template <class... Ts>
struct AllModesOf<TypeList<Ts...>> {
  using type = typename Concat<AllModes<Ts>...>::type;
};

template <class... Ts, class Fn>
void for_each_type(TypeList<Ts...>, Fn&& fn) {
  (fn(static_cast<Ts*>(nullptr)), ...);
}

template <FixedPoint T, class Fn>
void for_each_raw(Fn&& fn) {
  for (std::int64_t r = ref_min(shape_of<T>()); r <= ref_max(shape_of<T>()); ++r) fn(r);
}

// Left operands: every width 1..6; right operands: a spread of widths and
// scales, including Frac < 0 and Frac > Width.
using LeftOperands = Concat<BothSigns<0, 1, 2, 3, 4, 5, 6>, BothSigns<3, 1, 2, 3, 4, 5, 6>>::type;
using RightOperands =
    Concat<BothSigns<-1, 1, 3, 6>, BothSigns<2, 1, 4, 6>, BothSigns<7, 2, 5>>::type;

// ---- arithmetic and comparison ---------------------------------------------

template <class Ordering>
int sign_of(Ordering o) {
  return o < 0 ? -1 : (o > 0 ? 1 : 0);
}

// The value a result word stands for, read back without the library.
template <FixedPoint T>
long double value_read(const T& x) {
  return value_of(static_cast<std::int64_t>(x.raw()), T::frac);
}

template <FixedPoint A, FixedPoint B>
void check_pair(Tally& tally) {
  constexpr TypeInfo info_b = info_of<B>();
  for_each_raw<A>([&](std::int64_t ra) {
    for_each_raw<B>([&](std::int64_t rb) {
      const auto a = A::from_raw(ra);
      const auto b = B::from_raw(rb);
      const long double va = value_of(ra, A::frac);
      const long double vb = value_of(rb, B::frac);
      const auto check = [&](const char* what, long double got, long double want) {
        tally.check({what, info_of<A>(), ra, &info_b, rb, got, want});
      };
      // Exact: the result word holds the true value, not a wrapped one.
      check("a+b", value_read(a + b), va + vb);
      check("a-b", value_read(a - b), va - vb);
      check("a*b", value_read(a * b), va * vb);
      check("a<=>b", sign_of(a <=> b), sign_of(va <=> vb));
      check("a==b", a == b, va == vb);
      check("a<b", a < b, va < vb);
      check("a>=b", a >= b, va >= vb);
    });
  });
}

TEST(FixedExhaustive, AddSubMulCompareAreExact) {
  Tally tally;
  for_each_type(LeftOperands{}, [&]<class A>(A*) {
    for_each_type(RightOperands{}, [&]<class B>(B*) { check_pair<A, B>(tally); });
  });
  EXPECT_TALLY_CLEAN(tally);
}

TEST(FixedExhaustive, NegateIsExact) {
  Tally tally;
  for_each_type(LeftOperands{}, [&]<class A>(A*) {
    for_each_raw<A>([&](std::int64_t ra) {
      tally.check({"-a", info_of<A>(), ra, nullptr, 0, value_read(-A::from_raw(ra)),
                   -value_of(ra, A::frac)});
    });
  });
  EXPECT_TALLY_CLEAN(tally);
}

// ---- conversion -------------------------------------------------------------

// A 6-bit source at each scale covers every narrower source at that scale.
using Sources = Concat<BothSigns<-1, 6>, BothSigns<0, 6>, BothSigns<2, 6>, BothSigns<4, 6>,
                       BothSigns<7, 6>>::type;
using Targets = AllModesOf<Concat<BothSigns<-2, 1, 3>, BothSigns<0, 1, 3, 4>, BothSigns<1, 3>,
                                  BothSigns<3, 2, 4>, BothSigns<5, 3>>::type>::type;

TEST(FixedExhaustive, ConvertRoundsThenHandlesOverflow) {
  Tally tally;
  for_each_type(Sources{}, [&]<class S>(S*) {
    for_each_type(Targets{}, [&]<class T>(T*) {
      constexpr TypeInfo target = info_of<T>();
      for_each_raw<S>([&](std::int64_t rs) {
        const auto got = static_cast<std::int64_t>(convert<T>(S::from_raw(rs)).raw());
        const std::int64_t want =
            ref_quantise(value_of(rs, S::frac), target.shape, T::rounding, T::overflow);
        tally.check({"convert", info_of<S>(), rs, &target, 0, static_cast<long double>(got),
                     static_cast<long double>(want)});
      });
    });
  });
  EXPECT_TALLY_CLEAN(tally);
}

TEST(FixedExhaustive, FromDoubleOnGridHalfwayAndQuarterValues) {
  Tally tally;
  for_each_type(Targets{}, [&]<class T>(T*) {
    const Shape s = shape_of<T>();
    const std::int64_t span = std::int64_t{1} << T::width;
    // k runs past both ends of the range to exercise overflow; the failure
    // message reports x in quarter LSBs as "raw".
    for (std::int64_t k = ref_min(s) - span; k <= ref_max(s) + span; ++k) {
      for (std::int64_t quarter = 0; quarter < 4; ++quarter) {
        const double x = std::ldexp(static_cast<double>(4 * k + quarter), -T::frac - 2);
        const auto got = static_cast<std::int64_t>(T::from_double(x).raw());
        const std::int64_t want = ref_quantise(x, s, T::rounding, T::overflow);
        tally.check({"from_double", info_of<T>(), 4 * k + quarter, nullptr, 0,
                     static_cast<long double>(got), static_cast<long double>(want)});
      }
    }
  });
  EXPECT_TALLY_CLEAN(tally);
}

// ---- compound assignment ----------------------------------------------------

using Accumulators = AllModesOf<BothSigns<1, 4>>::type;
using Increments = Concat<BothSigns<0, 2>, BothSigns<3, 4>>::type;

TEST(FixedExhaustive, CompoundAssignmentRequantisesTheExactResult) {
  Tally tally;
  for_each_type(Accumulators{}, [&]<class A>(A*) {
    for_each_type(Increments{}, [&]<class B>(B*) {
      constexpr TypeInfo info_b = info_of<B>();
      for_each_raw<A>([&](std::int64_t ra) {
        for_each_raw<B>([&](std::int64_t rb) {
          const long double va = value_of(ra, A::frac);
          const long double vb = value_of(rb, B::frac);
          const Shape s = shape_of<A>();
          auto sum = A::from_raw(ra);
          sum += B::from_raw(rb);
          auto diff = A::from_raw(ra);
          diff -= B::from_raw(rb);
          auto prod = A::from_raw(ra);
          prod *= B::from_raw(rb);
          const auto check = [&](const char* what, const A& got, long double exact) {
            tally.check(
                {what, info_of<A>(), ra, &info_b, rb,
                 static_cast<long double>(static_cast<std::int64_t>(got.raw())),
                 static_cast<long double>(ref_quantise(exact, s, A::rounding, A::overflow))});
          };
          check("+=", sum, va + vb);
          check("-=", diff, va - vb);
          check("*=", prod, va * vb);
        });
      });
    });
  });
  EXPECT_TALLY_CLEAN(tally);
}

}  // namespace
}  // namespace ceilnav::fp
