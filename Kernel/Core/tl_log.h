/* Logging with levels, to stderr.  The level is set by the driver (option
 * -log_level) or the environment variable TALUS_LOG_LEVEL. */
#ifndef TL_LOG_H
#define TL_LOG_H

typedef enum { TL_LOG_ERROR = 0, TL_LOG_WARN, TL_LOG_INFO, TL_LOG_DEBUG } TlLogLevel;

void tl_log_set_level(TlLogLevel level);
TlLogLevel tl_log_get_level(void);
/* Parses "error", "warn", "info", "debug"; returns -1 when unknown. */
int tl_log_level_from_name(const char *name);
void tl_log(TlLogLevel level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define tl_info(...) tl_log(TL_LOG_INFO, __VA_ARGS__)
#define tl_warn(...) tl_log(TL_LOG_WARN, __VA_ARGS__)
#define tl_debug(...) tl_log(TL_LOG_DEBUG, __VA_ARGS__)

#endif
