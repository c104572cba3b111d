// Text of the sweeps' CSV (internal: runs.cpp, sweep.cpp): numbers as %.17g, quoted fields.
#pragma once
#include <cstdio>
#include <string>

namespace phynjo::runtime::detail {

/// A CSV field: quoted when it holds a comma, a quote or a line break.
inline std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c == '\n' || c == '\r' ? ' ' : c;
    }
    return q + "\"";
}

/// `v` as %.17g (the bits, read back exactly), appended to `out`.
inline void append_number(std::string& out, double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    out += buf;
}

} // namespace phynjo::runtime::detail
