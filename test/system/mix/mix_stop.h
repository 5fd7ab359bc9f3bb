/* The mix programs stop cleanly on SIGINT and SIGTERM: they set mix_stop_requested, which their loops watch, and
 * the programs then write what they have and exit 0. */
#ifndef TGW_MIX_STOP_H
#define TGW_MIX_STOP_H

#include <signal.h>
#include <string.h>

static volatile sig_atomic_t mix_stop_requested = 0;

static void mix_on_stop_signal(int signo) {
    (void)signo;
    mix_stop_requested = 1;
}

/* Without SA_RESTART: a signal ends a sleep or a wait early, so the loop sees the request at once. */
static inline void mix_stop_on_signals(void) {
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = mix_on_stop_signal;
    sigaction(SIGINT, &action, NULL);
    sigaction(SIGTERM, &action, NULL);
}

#endif
