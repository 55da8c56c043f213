// `ctl --json` answers parsed for real in end-to-end tests: the text goes through Python's json module
// (python3, already a build dependency: toolchain/operator-transcript.sh), and a Python expression over
// the parsed object `d` is printed (json.dumps of it), so a test asserts on values, not substrings.
// An answer that is not exactly one JSON object makes the query return "INVALID JSON: ...".
#pragma once

#include <cstdio>
#include <fstream>
#include <string>

namespace rescue::app::testing {

// What a shell command prints (stdout and stderr), its trailing newlines removed.
inline std::string command_output(const std::string& command) {
  std::string out;
  std::FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (p == nullptr) return "popen failed";
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, p)) > 0) out.append(buffer, n);
  (void)::pclose(p);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

// What Debian's Python prints for `script` (written to DIR/NAME.py) run on `text` (written to
// DIR/NAME.data, the script's last argument); `arguments` come first. Debian's interpreter, because
// toolchain/setup.sh installs the modules the scripts use (jsonschema) there.
inline std::string python_output(const std::string& dir, const std::string& name, const std::string& script,
                                 const std::string& text, const std::string& arguments = "") {
  const std::string data = dir + "/" + name + ".data";
  const std::string path = dir + "/" + name + ".py";
  std::ofstream(data) << text;
  std::ofstream(path) << script;
  return command_output("/usr/bin/python3 '" + path + "' " + arguments + " '" + data + "'");
}

// json.dumps(EXPR) for `d` = json.loads(text); `dir`: a writable directory for the two files.
inline std::string json_query(const std::string& dir, const std::string& text, const std::string& expr) {
  return python_output(dir, "query",
                       "import json, sys\n"
                       "try:\n"
                       "    d = json.loads(open(sys.argv[-1]).read())\n"
                       "except ValueError as e:\n"
                       "    print('INVALID JSON: ' + str(e)); sys.exit(0)\n"
                       "print(json.dumps(" + expr + "))\n",
                       text);
}

}  // namespace rescue::app::testing
