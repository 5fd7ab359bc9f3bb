/* A base-camp program as its users make it with Cyclone DDS, reading what mix_pub publishes: six readers with
 * Cyclone's default QoS but reliable (the readers ROS 2 makes; Cyclone's own default reader is best effort),
 * KEEP_LAST 1. MIX_BEST_EFFORT=1 keeps them best effort, for the comparison run. MIX_DEPTH=N keeps the last N
 * (ROS 2's default profile keeps 10). The participant takes its
 * configuration (peers, interface) from CYCLONEDDS_URI.
 *
 *   mix_sub DOMAIN SECONDS OUT_FILE [TOPIC...]
 *
 * TOPICs, when given, are read instead of mix_pub's, each as a Blob (mix_pub's paper workload, under the names a
 * base camp's relay gives them, such as rover1/telemetry/A).
 *
 * A waitset wakes the program as soon as a sample is there, and the arrival is stamped when it is taken. Each
 * valid sample appends "TOPIC SEQ SOURCE_NS ARRIVAL_NS INSTANCE" to OUT_FILE (wall-clock ns; INSTANCE the joint's
 * id, -1 for unkeyed topics), flushed every second and at exit. Exits 0 after SECONDS or on SIGTERM/SIGINT. */
#include <dds/dds.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "Mix.h"
#include "mix_stop.h"

#define MAX_SAMPLES 16

typedef enum mix_kind { MIX_TEXT, MIX_POSE, MIX_JOINT, MIX_BLOB } mix_kind;

/* The topics of mix_pub.c. */
typedef struct mix_topic {
    const char* name;
    mix_kind kind;
    const dds_topic_descriptor_t* desc;
    dds_entity_t reader;
    unsigned long received;
} mix_topic;

static void sample_ids(const mix_topic* t, const void* sample, uint32_t* seq, int32_t* instance) {
    *instance = -1;
    switch (t->kind) {
        case MIX_TEXT:
            *seq = ((const tgw_mix_Text*)sample)->seq;
            break;
        case MIX_POSE:
            *seq = ((const tgw_mix_Pose*)sample)->seq;
            break;
        case MIX_JOINT:
            *seq = ((const tgw_mix_Joint*)sample)->seq;
            *instance = ((const tgw_mix_Joint*)sample)->id;
            break;
        case MIX_BLOB:
            *seq = ((const tgw_mix_Blob*)sample)->seq;
            break;
    }
}

/* Takes everything the reader holds, one line per valid sample. */
static void take_all(mix_topic* t, FILE* out) {
    void* samples[MAX_SAMPLES];
    dds_sample_info_t infos[MAX_SAMPLES];
    for (;;) {
        samples[0] = NULL; /* loaned */
        const dds_return_t n = dds_take(t->reader, samples, infos, MAX_SAMPLES, MAX_SAMPLES);
        const dds_time_t arrival = dds_time();
        if (n <= 0)
            return;
        for (dds_return_t i = 0; i < n; ++i) {
            if (!infos[i].valid_data)
                continue;
            uint32_t seq = 0;
            int32_t instance = -1;
            sample_ids(t, samples[i], &seq, &instance);
            fprintf(out, "%s %u %lld %lld %d\n", t->name, (unsigned)seq, (long long)infos[i].source_timestamp,
                    (long long)arrival, (int)instance);
            ++t->received;
        }
        dds_return_loan(t->reader, samples, n);
        if (n < MAX_SAMPLES)
            return;
    }
}

#define MAX_TOPICS 16

int main(int argc, char** argv) {
    const double seconds = argc >= 4 ? atof(argv[2]) : 0.0;
    if (argc < 4 || seconds <= 0 || argc - 4 > MAX_TOPICS) {
        fprintf(stderr, "usage: mix_sub DOMAIN SECONDS OUT_FILE [TOPIC...] (at most %d)\n", MAX_TOPICS);
        return 2;
    }
    const int domain = atoi(argv[1]);
    const char* best_effort_env = getenv("MIX_BEST_EFFORT");
    const int best_effort = best_effort_env != NULL && strcmp(best_effort_env, "1") == 0;

    const mix_topic mix[] = {
        {"mix/hazard", MIX_TEXT, &tgw_mix_Text_desc, 0, 0},   {"mix/pose", MIX_POSE, &tgw_mix_Pose_desc, 0, 0},
        {"mix/joints", MIX_JOINT, &tgw_mix_Joint_desc, 0, 0}, {"mix/battery", MIX_TEXT, &tgw_mix_Text_desc, 0, 0},
        {"mix/image", MIX_BLOB, &tgw_mix_Blob_desc, 0, 0},    {"mix/science", MIX_BLOB, &tgw_mix_Blob_desc, 0, 0},
    };
    mix_topic topics[MAX_TOPICS];
    size_t n_topics = 0;
    if (argc > 4) {
        for (int i = 4; i < argc; ++i)
            topics[n_topics++] = (mix_topic){argv[i], MIX_BLOB, &tgw_mix_Blob_desc, 0, 0};
    } else {
        n_topics = sizeof mix / sizeof mix[0];
        memcpy(topics, mix, sizeof mix);
    }

    FILE* out = fopen(argv[3], "a");
    if (out == NULL) {
        fprintf(stderr, "mix_sub: cannot open %s\n", argv[3]);
        return 1;
    }
    const dds_entity_t participant = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
    if (participant < 0) {
        fprintf(stderr, "mix_sub: dds_create_participant: %s\n", dds_strretcode(-participant));
        fclose(out);
        return 1;
    }
    const dds_entity_t waitset = dds_create_waitset(participant);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, best_effort ? DDS_RELIABILITY_BEST_EFFORT : DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    const char* depth_env = getenv("MIX_DEPTH");
    if (depth_env != NULL && atoi(depth_env) > 0)
        dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, atoi(depth_env));
    for (size_t i = 0; i < n_topics; ++i) {
        mix_topic* t = &topics[i];
        const dds_entity_t topic = dds_create_topic(participant, t->desc, t->name, NULL, NULL);
        t->reader = topic < 0 ? topic : dds_create_reader(participant, topic, qos, NULL);
        const dds_entity_t condition = t->reader < 0 ? t->reader : dds_create_readcondition(t->reader, DDS_ANY_STATE);
        const dds_return_t attached =
            condition < 0 ? condition : dds_waitset_attach(waitset, condition, (dds_attach_t)i);
        if (attached < 0) {
            fprintf(stderr, "mix_sub: %s: cannot create the reader: %s\n", t->name, dds_strretcode(-attached));
            dds_delete_qos(qos);
            dds_delete(participant);
            fclose(out);
            return 1;
        }
    }
    dds_delete_qos(qos);

    mix_stop_on_signals();

    const dds_time_t end = dds_time() + (dds_duration_t)(seconds * 1e9);
    dds_time_t next_flush = dds_time() + DDS_SECS(1);
    dds_attach_t triggered[MAX_TOPICS];
    while (!mix_stop_requested) {
        const dds_time_t now = dds_time();
        if (now >= end)
            break;
        /* At most 100 ms, to see a signal and flush on time. */
        const dds_time_t wake = end < now + DDS_MSECS(100) ? end : now + DDS_MSECS(100);
        const dds_return_t n = dds_waitset_wait_until(waitset, triggered, n_topics, wake);
        for (dds_return_t i = 0; i < n; ++i)
            take_all(&topics[triggered[i]], out);
        if (dds_time() >= next_flush) {
            fflush(out);
            next_flush += DDS_SECS(1);
        }
    }

    fclose(out);
    for (size_t i = 0; i < n_topics; ++i)
        printf("mix_sub: %s received %lu\n", topics[i].name, topics[i].received);
    dds_delete(participant);
    return 0;
}
