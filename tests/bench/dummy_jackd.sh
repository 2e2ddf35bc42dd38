# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by the JACK bench scripts (soak, soak-scene, heap-per-scene, xrun-floor; not part of CI).
#
# Interface:
#   start_dummy_jackd SERVER PERIOD LOG   # jackd -d dummy at 48 kHz, PERIOD frames, under the name SERVER
#                                         # (exported as JACK_DEFAULT_SERVER), its output in LOG; sets
#                                         # $jack (its PID, for the caller's clean-up) and $mode
#
# Real-time scheduling when the machine allows it (as a live rig runs JACK); otherwise without, where the
# kernel may deschedule the audio thread past a period whatever it costs (those xruns are the machine's,
# and the scripts say which mode they ran in).
start_dummy_jackd() {
    local server="$1" period="$2" log="$3"
    export JACK_DEFAULT_SERVER="$server" JACK_NO_AUDIO_RESERVATION=1
    mode=realtime
    /usr/bin/jackd -R -P 70 -n "$server" -d dummy -r 48000 -p "$period" >"$log" 2>&1 &
    jack=$!
    sleep 2
    if ! kill -0 "$jack" 2>/dev/null; then
        mode=no-realtime
        /usr/bin/jackd --no-realtime -n "$server" -d dummy -r 48000 -p "$period" >"$log" 2>&1 &
        jack=$!
        sleep 2
    fi
}
