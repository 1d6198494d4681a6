// What a log's header must be (SPEC §2), for every way a log is made: the
// CSV reader and a log built from a table in memory (the Python module's
// numpy arrays and DataFrames). One owner, so both refuse the same headers
// with the same messages.
#pragma once

#include <string>
#include <vector>

#include "stac/log.hpp"

namespace stac::io {

// A time column's name (SPEC §2): "time", "t" or "timestamp".
bool isTimeName(const std::string& s);

// Checks `names` (the header's cells, trimmed) as the header on `line` of
// log->path and fills log->columns, log->time_name and log->header_line.
// Returns the time column's index in `names`, or -1. Throws InputError
// naming the line and column of an empty name, a name given twice or a
// second time column.
int readLogHeader(const std::vector<std::string>& names, int line, Log* log);

// The message for a frame whose time cell is missing.
std::string missingTimeMessage(const std::string& time_name);

}  // namespace stac::io
