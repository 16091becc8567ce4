// assert.hpp: REFRASTER_ASSERT, the run-time check of a precondition that a header states.
//
// Implements: REFRASTER_ASSERT(condition, message). Active in debug builds (NDEBUG not defined)
// and in checked builds (REFRASTER_CHECKED defined: the CMake option REFRASTER_CHECKED, and the
// core the unit tests link): a false condition prints the condition, the message and the place
// to stderr and aborts. Otherwise the condition is not evaluated and the macro costs nothing.
//
// Deliberately does not: handle bad input. Scenes, profiles and command lines are checked where
// they are read, and refused with an error; an assertion states a contract between the
// project's own parts, and its failure is a bug.
#pragma once

#if !defined(NDEBUG) || defined(REFRASTER_CHECKED)
#define REFRASTER_ASSERTIONS 1
#else
#define REFRASTER_ASSERTIONS 0
#endif

namespace refraster {

// Whether REFRASTER_ASSERT checks its condition in this build.
inline constexpr bool kAssertions = REFRASTER_ASSERTIONS != 0;

// Prints "file:line: precondition failed: condition (message)" to stderr and aborts.
[[noreturn]] void assertion_failed(const char* condition, const char* message, const char* file,
                                   int line) noexcept;

}  // namespace refraster

#if REFRASTER_ASSERTIONS
#define REFRASTER_ASSERT(condition, message) \
    ((condition) ? static_cast<void>(0)      \
                 : ::refraster::assertion_failed(#condition, message, __FILE__, __LINE__))
#else
#define REFRASTER_ASSERT(condition, message) static_cast<void>(sizeof(static_cast<bool>(condition)))
#endif
