/* Logging with levels, to stderr.  The level is read from the environment
 * variable TALUS_LOG_LEVEL (error, warn, info, debug; info when unset) at the
 * first message, and every program's -log_level option overrides it
 * (tl_options_create).  At "warn" and "error" the informational lines of the
 * library and of the drivers that print through tl_info are silent. */
#ifndef TL_LOG_H
#define TL_LOG_H

typedef enum { TL_LOG_ERROR = 0, TL_LOG_WARN, TL_LOG_INFO, TL_LOG_DEBUG } TlLogLevel;

void tl_log_set_level(TlLogLevel level);
/* (Re)reads TALUS_LOG_LEVEL and sets the level from it (a warning on stderr
 * when the value is not a level name); returns the level in force. */
TlLogLevel tl_log_from_environment(void);
TlLogLevel tl_log_get_level(void);
/* Parses "error", "warn" (or "warning"), "info", "debug", in any case;
 * returns -1 when unknown. */
int tl_log_level_from_name(const char *name);
void tl_log(TlLogLevel level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define tl_info(...) tl_log(TL_LOG_INFO, __VA_ARGS__)
#define tl_warn(...) tl_log(TL_LOG_WARN, __VA_ARGS__)
#define tl_debug(...) tl_log(TL_LOG_DEBUG, __VA_ARGS__)

#endif
