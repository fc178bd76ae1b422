# Sourced by sanitize.sh and fuzz.sh: runtime options every sanitized run here needs.
# intercept_tls_get_addr=0: up to GCC 13 and LLVM 16 the runtime's __tls_get_addr interceptor takes a dynamic TLS
# block that starts 16 bytes into a page for glibc 2.19's layout and reads a start and size from the two words before
# it. Since glibc 2.25 those blocks are plain malloc'd memory (a module loaded with dlopen gets one per thread), so
# one in 256 lands there by chance: the leak check at exit scans a made-up range and LeakSanitizer's tracer dies with
# "Tracer caught signal 11" after every test has passed. Without the interceptor those blocks are heap memory like any
# other, and the sanitized suite finds no leak in them.
export ASAN_OPTIONS="intercept_tls_get_addr=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
