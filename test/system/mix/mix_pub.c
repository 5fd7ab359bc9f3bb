/* A real robot's mix, as an independent Cyclone DDS program publishes it on the robot domain: six topics on one
 * participant with Cyclone's default settings, each writer with Cyclone's default QoS (reliable, KEEP_LAST 1)
 * except a Lifespan of the topic's TTL. It keeps an absolute periodic schedule: sample n of a topic is due at
 * t = n * period, however late the previous one was written; t = 0 is when every writer has matched a reader (the
 * gateway's), or 10 s after the start if one has not. Each sample is written with the wall clock at writing as source
 * timestamp and stamp_ns. seq counts per topic from 0; the six joints of one tick share it.
 *
 *   mix_pub DOMAIN SECONDS [paper]
 *
 * With "paper", the paper's workload instead, as an independent Cyclone program would publish it: telemetry/A to D,
 * Blob samples of 41, 66, 266 and 1016 bytes of data, 5 Hz each, Lifespans (TTLs) of 1, 2, 5 and 20 s.
 *
 * stdout: "mix_pub: start_ns T" (the wall clock at t = 0) at once, and at the end one line per topic
 * "mix_pub: TOPIC published N" (samples, so six per tick for mix/joints). */
#include <dds/dds.h>
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "Mix.h"
#include "mix_stop.h"

#define JOINTS 6
#define IMAGE_BYTES 6000
#define SCIENCE_BYTES 1500
#define MATCH_WAIT_S 10
#define MAX_TOPICS 6

typedef enum mix_kind { MIX_HAZARD, MIX_POSE, MIX_JOINTS, MIX_BATTERY, MIX_IMAGE, MIX_SCIENCE, MIX_PAPER } mix_kind;

typedef struct mix_topic {
    mix_kind kind;
    const char* name;
    const dds_topic_descriptor_t* desc;
    int64_t period_ns;
    int64_t ttl_ns;
    uint32_t blob_bytes; /* MIX_PAPER: its data's size */
    dds_entity_t writer;
    uint32_t seq;
    int64_t next_due_ns; /* monotonic */
    unsigned long published;
    unsigned long failed;
} mix_topic;

/* Scheduling runs on the monotonic clock, so that a step of the wall clock neither bunches nor skips samples. */
static int64_t monotonic_ns(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void sleep_until_monotonic(int64_t due_ns) {
    struct timespec ts;
    ts.tv_sec = (time_t)(due_ns / 1000000000);
    ts.tv_nsec = (long)(due_ns % 1000000000);
    /* A signal ends the sleep early (EINTR); the caller sees mix_stop_requested and the due time again. */
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
}

static void fill_bytes(uint8_t* buffer, uint32_t length, uint32_t seq) {
    for (uint32_t i = 0; i < length; ++i)
        buffer[i] = (uint8_t)((seq * 31u + i * 7u) & 0xffu);
}

static dds_return_t write_blob(const mix_topic* t, uint8_t* buffer, uint32_t length, dds_time_t stamp) {
    tgw_mix_Blob sample;
    sample.seq = t->seq;
    sample.stamp_ns = stamp;
    fill_bytes(buffer, length, t->seq);
    sample.data._length = sample.data._maximum = length;
    sample.data._buffer = buffer;
    sample.data._release = false;
    return dds_write_ts(t->writer, &sample, stamp);
}

/* Writes the topic's samples of one tick; returns how many were written. */
static unsigned write_tick(mix_topic* t, uint8_t* buffer) {
    char text[32];
    unsigned ok = 0;
    dds_return_t rc = DDS_RETCODE_OK;
    const dds_time_t stamp = dds_time();
    switch (t->kind) {
        case MIX_HAZARD:
        case MIX_BATTERY: {
            tgw_mix_Text sample;
            sample.seq = t->seq;
            sample.stamp_ns = stamp;
            if (t->kind == MIX_HAZARD) /* 24 characters */
                snprintf(text, sizeof text, "hazard %05u clear ahead", (unsigned)(t->seq % 100000u));
            else /* 8 characters */
                snprintf(text, sizeof text, "soc %03u%%", (unsigned)(100u - t->seq % 100u));
            sample.message = text;
            rc = dds_write_ts(t->writer, &sample, stamp);
            ok = rc == DDS_RETCODE_OK;
            break;
        }
        case MIX_POSE: {
            const double s = (double)t->seq;
            tgw_mix_Pose sample = {.seq = t->seq,
                                   .stamp_ns = stamp,
                                   .x = 0.1 * s,
                                   .y = 0.05 * s,
                                   .z = 0.0,
                                   .qx = 0.0,
                                   .qy = 0.0,
                                   .qz = 0.0,
                                   .qw = 1.0};
            rc = dds_write_ts(t->writer, &sample, stamp);
            ok = rc == DDS_RETCODE_OK;
            break;
        }
        case MIX_JOINTS:
            for (int32_t id = 0; id < JOINTS; ++id) {
                tgw_mix_Joint sample = {.seq = t->seq,
                                        .stamp_ns = stamp,
                                        .id = id,
                                        .position = 0.01 * (double)(t->seq + (uint32_t)id),
                                        .velocity = 0.01};
                const dds_return_t one = dds_write_ts(t->writer, &sample, stamp);
                if (one == DDS_RETCODE_OK)
                    ++ok;
                else
                    rc = one;
            }
            break;
        case MIX_IMAGE:
            rc = write_blob(t, buffer, IMAGE_BYTES, stamp);
            ok = rc == DDS_RETCODE_OK;
            break;
        case MIX_SCIENCE:
            rc = write_blob(t, buffer, SCIENCE_BYTES, stamp);
            ok = rc == DDS_RETCODE_OK;
            break;
        case MIX_PAPER:
            rc = write_blob(t, buffer, t->blob_bytes, stamp);
            ok = rc == DDS_RETCODE_OK;
            break;
    }
    if (rc != DDS_RETCODE_OK && t->failed++ == 0)
        fprintf(stderr, "mix_pub: %s: dds_write_ts: %s (reported once)\n", t->name, dds_strretcode(-rc));
    return ok;
}

int main(int argc, char** argv) {
    const double seconds = argc >= 3 ? atof(argv[2]) : 0.0;
    const int paper = argc == 4 && strcmp(argv[3], "paper") == 0;
    if (argc < 3 || argc > 4 || seconds <= 0 || (argc == 4 && !paper)) {
        fprintf(stderr, "usage: mix_pub DOMAIN SECONDS [paper]\n");
        return 2;
    }
    const int domain = atoi(argv[1]);

    const mix_topic mix[] = {
        {MIX_HAZARD, "mix/hazard", &tgw_mix_Text_desc, DDS_SECS(1), DDS_SECS(1), 0, 0, 0, 0, 0, 0},
        {MIX_POSE, "mix/pose", &tgw_mix_Pose_desc, DDS_MSECS(200), DDS_MSECS(1500), 0, 0, 0, 0, 0, 0},
        {MIX_JOINTS, "mix/joints", &tgw_mix_Joint_desc, DDS_SECS(1), DDS_SECS(2), 0, 0, 0, 0, 0, 0},
        {MIX_BATTERY, "mix/battery", &tgw_mix_Text_desc, DDS_SECS(1), DDS_SECS(5), 0, 0, 0, 0, 0, 0},
        {MIX_IMAGE, "mix/image", &tgw_mix_Blob_desc, DDS_SECS(2), DDS_SECS(20), 0, 0, 0, 0, 0, 0},
        {MIX_SCIENCE, "mix/science", &tgw_mix_Blob_desc, DDS_SECS(1), DDS_SECS(60), 0, 0, 0, 0, 0, 0},
    };
    const mix_topic paper_workload[] = {
        {MIX_PAPER, "telemetry/A", &tgw_mix_Blob_desc, DDS_MSECS(200), DDS_SECS(1), 41, 0, 0, 0, 0, 0},
        {MIX_PAPER, "telemetry/B", &tgw_mix_Blob_desc, DDS_MSECS(200), DDS_SECS(2), 66, 0, 0, 0, 0, 0},
        {MIX_PAPER, "telemetry/C", &tgw_mix_Blob_desc, DDS_MSECS(200), DDS_SECS(5), 266, 0, 0, 0, 0, 0},
        {MIX_PAPER, "telemetry/D", &tgw_mix_Blob_desc, DDS_MSECS(200), DDS_SECS(20), 1016, 0, 0, 0, 0, 0},
    };
    mix_topic topics[MAX_TOPICS];
    const size_t n_topics = paper ? sizeof paper_workload / sizeof paper_workload[0] : sizeof mix / sizeof mix[0];
    memcpy(topics, paper ? paper_workload : mix, n_topics * sizeof topics[0]);

    const dds_entity_t participant = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
    if (participant < 0) {
        fprintf(stderr, "mix_pub: dds_create_participant: %s\n", dds_strretcode(-participant));
        return 1;
    }
    for (size_t i = 0; i < n_topics; ++i) {
        mix_topic* t = &topics[i];
        const dds_entity_t topic = dds_create_topic(participant, t->desc, t->name, NULL, NULL);
        if (topic < 0) {
            fprintf(stderr, "mix_pub: %s: dds_create_topic: %s\n", t->name, dds_strretcode(-topic));
            dds_delete(participant);
            return 1;
        }
        dds_qos_t* qos = dds_create_qos();
        dds_qset_lifespan(qos, t->ttl_ns);
        t->writer = dds_create_writer(participant, topic, qos, NULL);
        dds_delete_qos(qos);
        if (t->writer < 0) {
            fprintf(stderr, "mix_pub: %s: dds_create_writer: %s\n", t->name, dds_strretcode(-t->writer));
            dds_delete(participant);
            return 1;
        }
    }

    mix_stop_on_signals();

    uint8_t* buffer = malloc(IMAGE_BYTES);
    if (buffer == NULL) {
        dds_delete(participant);
        return 1;
    }
    /* A robot's processes start with the gateway already there: t = 0 once every writer has matched a reader (the
     * gateway's), at most MATCH_WAIT_S later, so that the run counts from the first sample anyone could get. */
    const int64_t match_deadline_ns = monotonic_ns() + (int64_t)MATCH_WAIT_S * 1000000000;
    for (size_t i = 0; i < n_topics && !mix_stop_requested && monotonic_ns() < match_deadline_ns;) {
        dds_publication_matched_status_t matched;
        if (dds_get_publication_matched_status(topics[i].writer, &matched) == DDS_RETCODE_OK &&
            matched.current_count > 0) {
            ++i;
        } else {
            dds_sleepfor(DDS_MSECS(10));
        }
    }
    const int64_t start_ns = monotonic_ns();
    const dds_time_t start_wall_ns = dds_time();
    const int64_t end_ns = start_ns + (int64_t)(seconds * 1e9);
    printf("mix_pub: start_ns %lld\n", (long long)start_wall_ns);
    fflush(stdout);
    for (size_t i = 0; i < n_topics; ++i)
        topics[i].next_due_ns = start_ns;

    while (!mix_stop_requested) {
        mix_topic* next = &topics[0];
        for (size_t i = 1; i < n_topics; ++i) {
            if (topics[i].next_due_ns < next->next_due_ns)
                next = &topics[i];
        }
        if (next->next_due_ns >= end_ns)
            break;
        if (monotonic_ns() < next->next_due_ns) {
            sleep_until_monotonic(next->next_due_ns);
            continue; /* a signal may have woken us early: check again */
        }
        next->published += write_tick(next, buffer);
        ++next->seq;
        next->next_due_ns += next->period_ns;
    }

    for (size_t i = 0; i < n_topics; ++i)
        printf("mix_pub: %s published %lu\n", topics[i].name, topics[i].published);
    fflush(stdout);
    free(buffer);
    dds_delete(participant);
    return 0;
}
