// Command-line parsing shared by the subcommands: options declared with their help text,
// parsed strictly (unknown options and bad values are usage errors, exit code 2).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace hdof {

// Bad usage or bad input: the message is one line, the process exits with code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ArgParser {
 public:
  ArgParser(std::string command, std::string synopsis, std::string description);

  void flag(const std::string& name, const std::string& help, bool* out);
  void option(const std::string& name, const std::string& valueName, const std::string& help,
              std::string* out);
  void option(const std::string& name, const std::string& valueName, const std::string& help,
              double* out);
  void option(const std::string& name, const std::string& valueName, const std::string& help,
              float* out);
  void option(const std::string& name, const std::string& valueName, const std::string& help,
              uint32_t* out);
  void positional(const std::string& name, const std::string& help, std::string* out,
                  bool required = true);

  // Parses args (without the program and command names). Returns false when --help was asked
  // for (the help has been printed); throws UsageError on anything it does not understand.
  bool parse(std::span<const std::string> args);
  // Whether the option was given on the command line (after parse).
  bool given(const std::string& name) const;
  std::string help() const;

 private:
  struct Option {
    std::string name, valueName, help;
    std::function<void(const std::string&)> set;  // empty value for flags
    bool isFlag = false;
    bool seen = false;
  };
  struct Positional {
    std::string name, help;
    std::string* out;
    bool required;
  };
  std::string command_, synopsis_, description_;
  std::vector<Option> options_;
  std::vector<Positional> positionals_;
};

double parseNumber(const std::string& text, const std::string& what);
uint32_t parseCount(const std::string& text, const std::string& what);
struct Size2 {
  uint32_t width = 0, height = 0;
};
// "WxH", each at least 1 and at most maxSide.
Size2 parseSize(const std::string& text, uint32_t maxSide = 8192);

}  // namespace hdof
