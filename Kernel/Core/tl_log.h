/* Logging with levels.  The level is read from the environment variable
 * TALUS_LOG_LEVEL (error, warn, info, debug; info when unset) at the first
 * message, and every program's -log_level option overrides it
 * (tl_options_create).
 *
 * Two channels, one level:
 *  - stderr, tl_log() and tl_warn/tl_info/tl_debug: the library's messages
 *    and a driver's warnings, each a whole line ("warning: ", "debug: "
 *    prefixes; info lines bare);
 *  - stdout, tl_log_stdout() and tl_printf: a driver's report of its run
 *    (what it set up, tables, results), printf-like with no newline added,
 *    so a line may be built in pieces.
 * A message prints when its level is at most the level in force: at "warn"
 * and "error" the informational lines of both channels, and the progress bar
 * (tl_progress.h), are silent; at "debug" a driver adds detail (the options
 * it read, timings).
 *
 * Not subject to the level: the final "summary: ... status=..." line
 * (tl_summary.h), the run's result that scripts read, printed at every level;
 * the error that ends a run (tl_driver_exit); and what the user asked for,
 * the -help and -version text. */
#ifndef TL_LOG_H
#define TL_LOG_H

typedef enum { TL_LOG_ERROR = 0, TL_LOG_WARN, TL_LOG_INFO, TL_LOG_DEBUG } TlLogLevel;

void tl_log_set_level(TlLogLevel level);
/* (Re)reads TALUS_LOG_LEVEL and sets the level from it (a warning on stderr
 * when the value is not a level name); returns the level in force. */
TlLogLevel tl_log_from_environment(void);
TlLogLevel tl_log_get_level(void);
/* Whether a message of this level prints at the level in force. */
int tl_log_enabled(TlLogLevel level);
/* Parses "error", "warn" (or "warning"), "info", "debug", in any case;
 * returns -1 when unknown. */
int tl_log_level_from_name(const char *name);
/* A line on stderr, prefixed by its level, newline added. */
void tl_log(TlLogLevel level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Text on stdout as printf writes it (no prefix, no newline added). */
void tl_log_stdout(TlLogLevel level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define tl_info(...) tl_log(TL_LOG_INFO, __VA_ARGS__)
#define tl_warn(...) tl_log(TL_LOG_WARN, __VA_ARGS__)
#define tl_debug(...) tl_log(TL_LOG_DEBUG, __VA_ARGS__)
/* A driver's informational output on stdout. */
#define tl_printf(...) tl_log_stdout(TL_LOG_INFO, __VA_ARGS__)

#endif
