// SPDX-License-Identifier: LGPL-2.1-or-later
// This file is part of tkr-wear.
//
// BlasKernel: OpenBLAS's kernels for a processor newer than the library.

#include <tkr/elasticity/blas_kernel.h>

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <climits>
#include <cstdlib>

namespace TKR::Elasticity::BlasKernel
{
  namespace
  {
    // OpenBLAS's Intel line, oldest first: the cores its DYNAMIC_ARCH
    // falls back to (Prescott for an Intel model it does not know) and
    // those this processor's instructions allow.
    constexpr std::array<const char *, 8> intel_line = {{"Prescott",
                                                         "Core2",
                                                         "Penryn",
                                                         "Dunnington",
                                                         "Nehalem",
                                                         "Sandybridge",
                                                         "Haswell",
                                                         "SkylakeX"}};

    int
    rank_of(const std::string &core)
    {
      const auto same = [&core](const char *name) {
        const std::string other = name;
        return other.size() == core.size() &&
               std::equal(other.begin(),
                          other.end(),
                          core.begin(),
                          [](const char a, const char b) {
                            return std::tolower(a) == std::tolower(b);
                          });
      };
      const auto found =
        std::find_if(intel_line.begin(), intel_line.end(), same);
      return found == intel_line.end() ? -1 : found - intel_line.begin();
    }

    // The variable that tells the program run again which core OpenBLAS
    // had chosen (and that select() set OPENBLAS_CORETYPE).
    constexpr const char *fallback_variable = "TKR_OPENBLAS_FALLBACK_CORE";
  } // namespace

  Processor
  this_processor()
  {
    __builtin_cpu_init();
    Processor processor;
    processor.avx = __builtin_cpu_supports("avx");
    processor.avx2 =
      __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    processor.avx512 =
      __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq");
    return processor;
  }

  std::string
  better_core(const std::string &core, const Processor &processor)
  {
    // Only a core without AVX is a fallback: OpenBLAS chose Sandybridge,
    // Haswell or SkylakeX knowing the processor.
    const int chosen = rank_of(core);
    if (chosen < 0 || chosen >= rank_of("Sandybridge"))
      return "";
    // (each of them is above every fallback)
    return processor.avx512 ? "SkylakeX" :
           processor.avx2   ? "Haswell" :
           processor.avx    ? "Sandybridge" :
                              "";
  }

  void
  select(char *argv[])
  {
    if (std::getenv("OPENBLAS_CORETYPE") != nullptr)
      return; // the user's choice, or this program's before it ran again
    using CoreName = char *(*)();
    const auto core_name =
      reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
    if (core_name == nullptr || core_name() == nullptr)
      return; // not OpenBLAS
    const std::string core   = core_name();
    const std::string better = better_core(core, this_processor());
    if (better.empty())
      return;
    // The executable's own path, not /proc/self/exe: the process keeps its
    // name (ps, pkill -x tkr-wear).
    char          path[PATH_MAX];
    const ssize_t length = readlink("/proc/self/exe", path, sizeof(path) - 1);
    if (length <= 0)
      return;
    path[length] = '\0';
    setenv("OPENBLAS_CORETYPE", better.c_str(), 1);
    setenv(fallback_variable, core.c_str(), 1);
    execv(path, argv);
    // (could not run again: go on with the kernels OpenBLAS chose)
    unsetenv("OPENBLAS_CORETYPE");
    unsetenv(fallback_variable);
  }

  std::string
  note()
  {
    const char *fallback = std::getenv(fallback_variable);
    const char *core     = std::getenv("OPENBLAS_CORETYPE");
    if (fallback == nullptr || core == nullptr)
      return "";
    return std::string("OpenBLAS's ") + core + " kernels (it chose " +
           fallback +
           " on this processor, which it does not know; "
           "OPENBLAS_CORETYPE overrides)";
  }
} // namespace TKR::Elasticity::BlasKernel
