#pragma once
// Logs to the systemd journal when the program's stderr is connected to it.
//
// Under systemd, stderr already reaches the journal as plain text at one
// priority. Writing through spdlog's systemd sink instead gives every line
// its priority (journalctl -p warning shows the link guard's actions and the
// errors), SYSLOG_IDENTIFIER=<identifier> and the journal's own timestamp.
// Connected means what systemd.exec(5) says: $JOURNAL_STREAM names the
// device and inode of stderr. Anywhere else (a terminal, a test) the
// loggers keep writing to stderr.

#include <string>

namespace ecpair::systemd {

// True when the loggers now write to the journal.
bool log_to_journal_if_connected(const std::string& identifier);

// Whether $JOURNAL_STREAM names the file behind `fd` (exposed for tests).
bool is_journal_stream(int fd, const char* journal_stream);

}  // namespace ecpair::systemd
