// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Streams interleaved float audio to a WAV file from its own thread, so the render thread never
// touches the disk.
//
// Interface:
//   WavWriter w(path, channels, sample_rate);   // opens the file (throws std::runtime_error) and starts
//                                               // the writer thread
//   render thread:  w.push(interleaved, frames) // false when the ring is full (the caller counts it)
//                   w.space_frames()            // room left, for an offline render that waits
//   control thread: w.reopen()                  // SIGHUP: finalise this file, start a new one (see below)
//                   w.close()                   // drain, finalise; also done by the destructor
//                   w.path(), w.frames_written(), w.frames_lost()
//                   w.take_error()              // the next disk event, once, oldest first; "" when none
//                   w.set_comment(text)         // before audio starts: the calibration, in this file and every
//                                               // later one (RIFF LIST/INFO ICMT, libsndfile's SF_STR_COMMENT)
//
// Nothing a user made is lost: the header is rewritten about once a second (libsndfile's
// SFC_UPDATE_HEADER_NOW), so even after SIGKILL the file reads back up to the last second; close()
// finalises it. reopen() never overwrites: if a file still stands at the path (it was not rotated
// away), the new one gets a -1, -2, ... suffix. Samples are 32-bit float, so a WAV is bit-exact with
// what JACK would have played.
//
// Faults never stop the audio: the writer thread keeps draining the ring whatever the disk does.
// - A write that fails (disk full, I/O error): reported once with the reason, then the samples that
//   cannot be written are dropped and counted (frames_lost); writing resumes by itself when the disk
//   takes data again, reported once more. What was written before stays readable (the header is
//   rewritten in place, which needs no new disk space).
// - The file removed while writing (checked about once a second: fstat's link count is 0): reported,
//   and the stream continues in a new file at the same path, so nothing more is lost into a file no
//   one can open.

#include <atomic>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "server/realtime/spsc_ring.hpp"

typedef struct sf_private_tag SNDFILE;

namespace ameoto {

class WavWriter {
public:
    WavWriter(std::string path, int channels, double sample_rate, double buffer_seconds = 4.0);
    ~WavWriter();
    WavWriter(const WavWriter&) = delete;
    WavWriter& operator=(const WavWriter&) = delete;

    bool push(const float* interleaved, int frames);
    std::size_t space_frames() const { return ring_.write_available() / static_cast<std::size_t>(channels_); }
    bool drained() const { return ring_.write_available() == ring_.capacity(); }

    void reopen();
    void close();

    std::string path() const;
    std::uint64_t frames_written() const { return frames_written_.load(); }
    std::uint64_t frames_lost() const { return frames_lost_.load(); }
    std::string take_error();
    void set_comment(const std::string& text);

private:
    void run();
    void open_file(const std::string& path);
    void close_file();
    void write_pending();
    void check_still_linked();
    void report(std::string event);   // with file_mutex_ held

    std::string requested_path_;
    const int channels_;
    const double sample_rate_;
    SpscRing<float> ring_;
    mutable std::mutex file_mutex_;   // guards file_, path_, error_ (never taken by the render thread)
    SNDFILE* file_ = nullptr;
    int fd_ = -1;                     // file_'s descriptor, for the link count
    bool failing_ = false;            // the last write failed (reported once until writes succeed again)
    std::string path_;
    std::string comment_;
    std::deque<std::string> events_;
    std::atomic<std::uint64_t> frames_written_{0};
    std::atomic<std::uint64_t> frames_lost_{0};
    std::atomic<bool> stop_{false};
    std::atomic<bool> reopen_{false};
    std::thread thread_;
};

// A path that does not exist yet: `path` itself, else path with -1, -2, ... before the extension.
std::string unused_path(const std::string& path);

}  // namespace ameoto
