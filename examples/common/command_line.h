// Command-line options and fatal errors of the example programs: each
// example declares its options once (name, value placeholder, target, help)
// and gets parsing, validation, --help and the usage text from this table.
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <superdex/superdex.h>

namespace superdex::examples {

inline std::string& ProgramName() {
  static std::string name = "superdex";
  return name;
}

/// Prints "<program>: <what>" and exits with status 1.
[[noreturn]] inline void Fail(std::string const& what) {
  std::fprintf(stderr, "%s: %s\n", ProgramName().c_str(), what.c_str());
  std::exit(1);
}

[[noreturn]] inline void Fail(std::string const& what, Error const& error) {
  Fail(what + ": " + error.ToString());
}

class CommandLine {
 public:
  explicit CommandLine(std::string program) { ProgramName() = std::move(program); }

  CommandLine& Text(std::string name, std::string value, std::string& target, std::string help) {
    return Add(std::move(name), std::move(value), std::move(help), [&target](std::string const& v) { target = v; });
  }
  /// A finite number > 0 (or >= 0 with `allowZero`).
  CommandLine& Number(std::string name, std::string value, real& target, std::string help,
                      bool allowZero = false) {
    return Add(name, std::move(value), std::move(help), [name, &target, allowZero](std::string const& v) {
      char* end = nullptr;
      double const x = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !std::isfinite(x) || x < 0 || (x == 0 && !allowZero))
        Fail(name + " needs a finite number " + (allowZero ? ">= 0" : "> 0") + ", got '" + v + "'");
      target = static_cast<real>(x);
    });
  }
  /// A positive integer.
  CommandLine& Count(std::string name, std::string value, int& target, std::string help) {
    return Add(name, std::move(value), std::move(help),
               [name, &target](std::string const& v) { target = ParseCount(name, v); });
  }
  /// N positive integers separated by commas.
  template <std::size_t N>
  CommandLine& Counts(std::string name, std::string value, std::array<int, N>& target, std::string help) {
    return Add(name, std::move(value), std::move(help), [name, &target](std::string const& v) {
      std::size_t start = 0;
      for (std::size_t k = 0; k < N; ++k) {
        std::size_t const comma = v.find(',', start);
        if ((k + 1 < N) != (comma != std::string::npos))
          Fail(name + " needs " + std::to_string(N) + " positive integers separated by commas, got '" + v + "'");
        target[k] = ParseCount(name, v.substr(start, comma == std::string::npos ? comma : comma - start));
        start = comma + 1;
      }
    });
  }
  /// "be" (backward Euler) or "bdf2".
  CommandLine& Integrator(std::string name, IntegratorType& target, std::string help) {
    return Add(name, "be|bdf2", std::move(help), [name, &target](std::string const& v) {
      if (v == "be")
        target = IntegratorType::BackwardEuler;
      else if (v == "bdf2")
        target = IntegratorType::Bdf2;
      else
        Fail(name + " must be 'be' or 'bdf2', got '" + v + "'");
    });
  }

  /// "stvk" or "tension-field" (MembraneModel).
  CommandLine& Membrane(std::string name, MembraneModel& target, std::string help) {
    return Add(name, "stvk|tension-field", std::move(help), [name, &target](std::string const& v) {
      if (v == "stvk")
        target = MembraneModel::StVK;
      else if (v == "tension-field")
        target = MembraneModel::TensionField;
      else
        Fail(name + " must be 'stvk' or 'tension-field', got '" + v + "'");
    });
  }

  /// Applies argv; --help prints the usage and exits 0, a bad option or
  /// value prints the usage and fails.
  void Parse(int argc, char** argv) const {
    for (int i = 1; i < argc; ++i) {
      std::string const arg = argv[i];
      if (arg == "-h" || arg == "--help") {
        PrintUsage(stdout);
        std::exit(0);
      }
      Option const* option = nullptr;
      for (Option const& o : options_)
        if (o.name == arg) option = &o;
      if (!option) {
        PrintUsage(stderr);
        Fail("unknown option '" + arg + "'");
      }
      if (i + 1 >= argc) {
        PrintUsage(stderr);
        Fail("missing value for '" + arg + "'");
      }
      option->set(argv[++i]);
    }
  }

 private:
  struct Option {
    std::string name, value, help;
    std::function<void(std::string const&)> set;
  };

  static int ParseCount(std::string const& name, std::string const& v) {
    char* end = nullptr;
    long const x = std::strtol(v.c_str(), &end, 10);
    if (end == v.c_str() || *end != '\0' || x < 1 || x > 100000)
      Fail(name + " needs a positive integer, got '" + v + "'");
    return static_cast<int>(x);
  }

  CommandLine& Add(std::string name, std::string value, std::string help,
                   std::function<void(std::string const&)> set) {
    options_.push_back({std::move(name), std::move(value), std::move(help), std::move(set)});
    return *this;
  }

  void PrintUsage(std::FILE* f) const {
    std::fprintf(f, "usage: %s [options]\n", ProgramName().c_str());
    for (Option const& o : options_) {
      std::string const flag = o.name + " " + o.value;
      std::fprintf(f, "  %-22s %s\n", flag.c_str(), o.help.c_str());
    }
  }

  std::vector<Option> options_;
};

}  // namespace superdex::examples
