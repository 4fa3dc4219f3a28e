/* Test harness only (LD_PRELOAD): lets libserialport open a pseudo-terminal.
 *
 * libserialport's sp_open() reads and sets the modem control lines (TIOCMGET and friends),
 * which a Linux pty does not implement (ENOTTY): it has no modem lines.  This shim answers
 * those four ioctls as "no lines asserted" when the kernel says ENOTTY, and passes
 * everything else through, so the pty tests can exercise the real libserialport backend
 * (framing, time-outs, reads and writes) against stim-emu.  Production code never loads it. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdarg.h>
#include <sys/ioctl.h>

int ioctl(int fd, unsigned long request, ...) {
  static int (*real_ioctl)(int, unsigned long, ...) = 0;
  va_list ap;
  va_start(ap, request);
  void* arg = va_arg(ap, void*);
  va_end(ap);
  if (!real_ioctl) real_ioctl = (int (*)(int, unsigned long, ...))dlsym(RTLD_NEXT, "ioctl");
  const int r = real_ioctl(fd, request, arg);
  if (r < 0 && errno == ENOTTY &&
      (request == TIOCMGET || request == TIOCMSET || request == TIOCMBIS || request == TIOCMBIC)) {
    if (request == TIOCMGET && arg) *(int*)arg = 0;
    return 0;
  }
  return r;
}
