#include "app/cli.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace hdof {

ArgParser::ArgParser(std::string command, std::string synopsis, std::string description)
    : command_(std::move(command)),
      synopsis_(std::move(synopsis)),
      description_(std::move(description)) {}

void ArgParser::flag(const std::string& name, const std::string& help, bool* out) {
  options_.push_back({name, "", help, [out](const std::string&) { *out = true; }, true});
}

void ArgParser::option(const std::string& name, const std::string& valueName,
                       const std::string& help, std::string* out) {
  options_.push_back({name, valueName, help, [out](const std::string& v) { *out = v; }});
}

void ArgParser::option(const std::string& name, const std::string& valueName,
                       const std::string& help, double* out) {
  options_.push_back(
      {name, valueName, help, [out, name](const std::string& v) { *out = parseNumber(v, name); }});
}

void ArgParser::option(const std::string& name, const std::string& valueName,
                       const std::string& help, float* out) {
  options_.push_back({name, valueName, help, [out, name](const std::string& v) {
                        *out = static_cast<float>(parseNumber(v, name));
                      }});
}

void ArgParser::option(const std::string& name, const std::string& valueName,
                       const std::string& help, uint32_t* out) {
  options_.push_back(
      {name, valueName, help, [out, name](const std::string& v) { *out = parseCount(v, name); }});
}

void ArgParser::positional(const std::string& name, const std::string& help, std::string* out,
                           bool required) {
  positionals_.push_back({name, help, out, required});
}

bool ArgParser::parse(std::span<const std::string> args) {
  size_t nextPositional = 0;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(help().c_str(), stdout);
      return false;
    }
    if (arg.size() > 2 && arg.starts_with("--")) {
      std::string name = arg, value;
      bool hasInlineValue = false;
      if (auto eq = arg.find('='); eq != std::string::npos) {
        name = arg.substr(0, eq);
        value = arg.substr(eq + 1);
        hasInlineValue = true;
      }
      Option* found = nullptr;
      for (Option& o : options_)
        if (o.name == name) found = &o;
      if (!found)
        throw UsageError("unknown option " + name + " for 'hdof " + command_ + "' (see hdof " +
                         command_ + " --help)");
      if (found->isFlag) {
        if (hasInlineValue) throw UsageError("option " + name + " takes no value");
      } else if (!hasInlineValue) {
        if (i + 1 >= args.size())
          throw UsageError("option " + name + " needs a value (" + found->valueName + ")");
        value = args[++i];
      }
      found->set(value);
      found->seen = true;
      continue;
    }
    if (nextPositional >= positionals_.size())
      throw UsageError("unexpected argument '" + arg + "' for 'hdof " + command_ + "' (see hdof " +
                       command_ + " --help)");
    *positionals_[nextPositional++].out = arg;
  }
  for (size_t p = nextPositional; p < positionals_.size(); ++p)
    if (positionals_[p].required)
      throw UsageError("'hdof " + command_ + "' needs " + positionals_[p].name + " (see hdof " +
                       command_ + " --help)");
  return true;
}

bool ArgParser::given(const std::string& name) const {
  for (const Option& o : options_)
    if (o.name == name) return o.seen;
  return false;
}

std::string ArgParser::help() const {
  std::ostringstream out;
  out << "usage: hdof " << command_ << " " << synopsis_ << "\n\n" << description_ << "\n";
  if (!positionals_.empty()) {
    out << "\narguments:\n";
    for (const Positional& p : positionals_) {
      out << "  " << p.name;
      out << std::string(p.name.size() < 26 ? 26 - p.name.size() : 1, ' ') << p.help << "\n";
    }
  }
  out << "\noptions:\n";
  for (const Option& o : options_) {
    std::string left = o.name + (o.valueName.empty() ? "" : " " + o.valueName);
    out << "  " << left << std::string(left.size() < 26 ? 26 - left.size() : 1, ' ') << o.help
        << "\n";
  }
  out << "  --help                    show this help\n";
  return out.str();
}

double parseNumber(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value))
    throw UsageError(what + ": '" + text + "' is not a finite number");
  return value;
}

uint32_t parseCount(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])) ||
      end != text.c_str() + text.size() || errno == ERANGE || value > 0xffffffffull)
    throw UsageError(what + ": '" + text + "' is not a whole number from 0 to 4294967295");
  return static_cast<uint32_t>(value);
}

Size2 parseSize(const std::string& text, uint32_t maxSide) {
  auto x = text.find('x');
  if (x == std::string::npos)
    throw UsageError("size '" + text + "' is not WIDTHxHEIGHT, e.g. 640x360");
  Size2 size;
  try {
    size.width = parseCount(text.substr(0, x), "width");
    size.height = parseCount(text.substr(x + 1), "height");
  } catch (const UsageError&) {
    throw UsageError("size '" + text + "' is not WIDTHxHEIGHT, e.g. 640x360");
  }
  if (size.width < 1 || size.height < 1 || size.width > maxSide || size.height > maxSide)
    throw UsageError("size " + text + " is out of range: each side must be 1 to " +
                     std::to_string(maxSide) + " pixels");
  return size;
}

}  // namespace hdof
