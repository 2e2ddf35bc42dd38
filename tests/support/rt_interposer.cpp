// SPDX-License-Identifier: GPL-3.0-or-later
// The real-time probe: replaces the C library's allocation, locking, sleeping and writing functions,
// and counts every call made while the calling thread is inside rt::Scope (server/realtime/rt_probe.hpp).
//
// Interface (C, found by dlsym or linked directly):
//   ameoto_rt_probe_enter() / ameoto_rt_probe_leave()   // rt::Scope calls these
//   ameoto_rt_probe_violations()                        // calls counted inside a scope
//   ameoto_rt_probe_first_violation()                   // name of the first offending function
//   ameoto_rt_probe_entries()                           // scopes entered (proves the probe was live)
//   ameoto_rt_probe_reset()
// At exit, when AMEOTO_RT_REPORT names a file, it writes "entries N\nviolations N\nfirst NAME\n" there.
//
// Why an interposer: it checks the real binary, built by the project's own compiler, with no change to
// the code under test; the daemon finds the probe by name only when it is preloaded. The replacement
// functions forward to glibc (__libc_malloc and friends; dlsym(RTLD_NEXT) for the rest), so programs
// behave as before; they only count. The per-thread flag uses the initial-exec TLS model so reading it
// never allocates (a dynamic TLS access could call malloc from inside malloc).

#include <dlfcn.h>
#include <pthread.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#if defined(AMEOTO_RT_UNDER_ASAN)
// Under AddressSanitizer (scripts/build-sanitized; this file itself is built without instrumentation) the heap is ASan's: forward to its allocator
// (libasan's interceptors), never to glibc's, or a block ASan handed out (operator new, strdup)
// would reach glibc's free. The probe counts exactly as in the normal build.
extern "C" {
void* __interceptor_malloc(size_t);
void* __interceptor_calloc(size_t, size_t);
void* __interceptor_realloc(void*, size_t);
void* __interceptor_memalign(size_t, size_t);
void __interceptor_free(void*);
}
#define AMEOTO_REAL_MALLOC __interceptor_malloc
#define AMEOTO_REAL_CALLOC __interceptor_calloc
#define AMEOTO_REAL_REALLOC __interceptor_realloc
#define AMEOTO_REAL_MEMALIGN __interceptor_memalign
#define AMEOTO_REAL_FREE __interceptor_free
#else
extern "C" {
void* __libc_malloc(size_t);
void* __libc_calloc(size_t, size_t);
void* __libc_realloc(void*, size_t);
void* __libc_memalign(size_t, size_t);
void __libc_free(void*);
}
#define AMEOTO_REAL_MALLOC __libc_malloc
#define AMEOTO_REAL_CALLOC __libc_calloc
#define AMEOTO_REAL_REALLOC __libc_realloc
#define AMEOTO_REAL_MEMALIGN __libc_memalign
#define AMEOTO_REAL_FREE __libc_free
#endif

namespace {

__attribute__((tls_model("initial-exec"))) thread_local int rt_depth = 0;
std::atomic<unsigned long> violations{0};
std::atomic<unsigned long> entries{0};
std::atomic<const char*> first_violation{nullptr};

inline void check(const char* what) {
    if (rt_depth > 0) {
        const char* expected = nullptr;
        first_violation.compare_exchange_strong(expected, what);
        violations.fetch_add(1, std::memory_order_relaxed);
    }
}

template <typename F>
F next(const char* name) {
    return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

// Resolved before main (dlsym may allocate; that is fine outside any scope).
using mutex_fn = int (*)(pthread_mutex_t*);
using cond_wait_fn = int (*)(pthread_cond_t*, pthread_mutex_t*);
using cond_timedwait_fn = int (*)(pthread_cond_t*, pthread_mutex_t*, const struct timespec*);
using nanosleep_fn = int (*)(const struct timespec*, struct timespec*);
using clock_nanosleep_fn = int (*)(clockid_t, int, const struct timespec*, struct timespec*);
using usleep_fn = int (*)(useconds_t);
using write_fn = ssize_t (*)(int, const void*, size_t);
using fwrite_fn = size_t (*)(const void*, size_t, size_t, FILE*);
using fputs_fn = int (*)(const char*, FILE*);
using puts_fn = int (*)(const char*);
using vfprintf_fn = int (*)(FILE*, const char*, va_list);
using vprintf_fn = int (*)(const char*, va_list);
using rwlock_fn = int (*)(pthread_rwlock_t*);
using sem_fn = int (*)(void*);

struct Real {
    mutex_fn mutex_lock = next<mutex_fn>("pthread_mutex_lock");
    mutex_fn mutex_trylock = next<mutex_fn>("pthread_mutex_trylock");
    cond_wait_fn cond_wait = next<cond_wait_fn>("pthread_cond_wait");
    cond_timedwait_fn cond_timedwait = next<cond_timedwait_fn>("pthread_cond_timedwait");
    rwlock_fn rdlock = next<rwlock_fn>("pthread_rwlock_rdlock");
    rwlock_fn wrlock = next<rwlock_fn>("pthread_rwlock_wrlock");
    sem_fn sem_wait = next<sem_fn>("sem_wait");
    nanosleep_fn nanosleep_ = next<nanosleep_fn>("nanosleep");
    clock_nanosleep_fn clock_nanosleep_ = next<clock_nanosleep_fn>("clock_nanosleep");
    usleep_fn usleep_ = next<usleep_fn>("usleep");
    write_fn write_ = next<write_fn>("write");
    fwrite_fn fwrite_ = next<fwrite_fn>("fwrite");
    fputs_fn fputs_ = next<fputs_fn>("fputs");
    puts_fn puts_ = next<puts_fn>("puts");
    vfprintf_fn vfprintf_ = next<vfprintf_fn>("vfprintf");
    vprintf_fn vprintf_ = next<vprintf_fn>("vprintf");
};
Real& real() {
    static Real r;
    return r;
}

struct Reporter {
    Reporter() { real(); }
    ~Reporter() {
        const char* path = std::getenv("AMEOTO_RT_REPORT");
        if (!path) return;
        FILE* f = std::fopen(path, "w");
        if (!f) return;
        const char* first = first_violation.load();
        std::fprintf(f, "entries %lu\nviolations %lu\nfirst %s\n", entries.load(), violations.load(), first ? first : "none");
        std::fclose(f);
    }
} reporter;

}  // namespace

extern "C" {

void ameoto_rt_probe_enter() {
    ++rt_depth;
    entries.fetch_add(1, std::memory_order_relaxed);
}
void ameoto_rt_probe_leave() { --rt_depth; }
unsigned long ameoto_rt_probe_violations() { return violations.load(); }
unsigned long ameoto_rt_probe_entries() { return entries.load(); }
const char* ameoto_rt_probe_first_violation() {
    const char* f = first_violation.load();
    return f ? f : "none";
}
void ameoto_rt_probe_reset() {
    violations.store(0);
    entries.store(0);
    first_violation.store(nullptr);
}

// Allocation
void* malloc(size_t n) {
    check("malloc");
    return AMEOTO_REAL_MALLOC(n);
}
void* calloc(size_t n, size_t s) {
    check("calloc");
    return AMEOTO_REAL_CALLOC(n, s);
}
void* realloc(void* p, size_t n) {
    check("realloc");
    return AMEOTO_REAL_REALLOC(p, n);
}
void free(void* p) {
    if (p) check("free");
    AMEOTO_REAL_FREE(p);
}
void* memalign(size_t a, size_t n) {
    check("memalign");
    return AMEOTO_REAL_MEMALIGN(a, n);
}
void* aligned_alloc(size_t a, size_t n) {
    check("aligned_alloc");
    return AMEOTO_REAL_MEMALIGN(a, n);
}
int posix_memalign(void** out, size_t a, size_t n) {
    check("posix_memalign");
    void* p = AMEOTO_REAL_MEMALIGN(a, n);
    if (!p) return 12;   // ENOMEM
    *out = p;
    return 0;
}

#if defined(AMEOTO_RT_UNDER_ASAN)
// ASan's own operator new does not call malloc, so the probe would not see `new` on the audio thread.
// These route it through the probe's malloc (and delete through free, every non-aligned form, so each
// block is freed the way it was allocated); aligned new and delete stay ASan's, a consistent pair.
}  // extern "C"
void* operator new(size_t n) {
    if (void* p = malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](size_t n) { return operator new(n); }
void* operator new(size_t n, const std::nothrow_t&) noexcept { return malloc(n ? n : 1); }
void* operator new[](size_t n, const std::nothrow_t&) noexcept { return malloc(n ? n : 1); }
void operator delete(void* p) noexcept { free(p); }
void operator delete[](void* p) noexcept { free(p); }
void operator delete(void* p, size_t) noexcept { free(p); }
void operator delete[](void* p, size_t) noexcept { free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { free(p); }
extern "C" {
#endif

// Locks and waits
int pthread_mutex_lock(pthread_mutex_t* m) {
    check("pthread_mutex_lock");
    return real().mutex_lock(m);
}
int pthread_mutex_trylock(pthread_mutex_t* m) {
    check("pthread_mutex_trylock");
    return real().mutex_trylock(m);
}
int pthread_cond_wait(pthread_cond_t* c, pthread_mutex_t* m) {
    check("pthread_cond_wait");
    return real().cond_wait(c, m);
}
int pthread_cond_timedwait(pthread_cond_t* c, pthread_mutex_t* m, const struct timespec* t) {
    check("pthread_cond_timedwait");
    return real().cond_timedwait(c, m, t);
}
int pthread_rwlock_rdlock(pthread_rwlock_t* l) {
    check("pthread_rwlock_rdlock");
    return real().rdlock(l);
}
int pthread_rwlock_wrlock(pthread_rwlock_t* l) {
    check("pthread_rwlock_wrlock");
    return real().wrlock(l);
}
int sem_wait(void* s) {
    check("sem_wait");
    return real().sem_wait(s);
}
int nanosleep(const struct timespec* t, struct timespec* rem) {
    check("nanosleep");
    return real().nanosleep_(t, rem);
}
int clock_nanosleep(clockid_t c, int flags, const struct timespec* t, struct timespec* rem) {
    check("clock_nanosleep");
    return real().clock_nanosleep_(c, flags, t, rem);
}
int usleep(useconds_t us) {
    check("usleep");
    return real().usleep_(us);
}

// Logging and other writes
ssize_t write(int fd, const void* buf, size_t n) {
    check("write");
    return real().write_(fd, buf, n);
}
size_t fwrite(const void* p, size_t s, size_t n, FILE* f) {
    check("fwrite");
    return real().fwrite_(p, s, n, f);
}
int fputs(const char* s, FILE* f) {
    check("fputs");
    return real().fputs_(s, f);
}
int puts(const char* s) {
    check("puts");
    return real().puts_(s);
}
int vfprintf(FILE* f, const char* fmt, va_list ap) {
    check("vfprintf");
    return real().vfprintf_(f, fmt, ap);
}
int fprintf(FILE* f, const char* fmt, ...) {
    check("fprintf");
    va_list ap;
    va_start(ap, fmt);
    const int r = real().vfprintf_(f, fmt, ap);
    va_end(ap);
    return r;
}
int printf(const char* fmt, ...) {
    check("printf");
    va_list ap;
    va_start(ap, fmt);
    const int r = real().vprintf_(fmt, ap);
    va_end(ap);
    return r;
}

}  // extern "C"
