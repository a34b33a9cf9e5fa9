/* A ROS 2 peer of another DDS implementation, Cyclone DDS (Debian's C library, with its DDS
 * Security plugins; no ROS): reads the MCM node's joint states, or publishes a trajectory to
 * it. Its security (an SROS2 enclave, or none) is Cyclone's configuration in CYCLONEDDS_URI.
 * Run by tests/end_to_end/ros2_security.rs.
 *
 *   secure_peer read DOMAIN NAMESPACE COUNT TIMEOUT_S
 *     prints `ok joint_states messages=N` and `at: name=deg ...` (the last message), or
 *     `FAILED: ...` and exits 1 when COUNT messages do not come within TIMEOUT_S.
 *   secure_peer trajectory DOMAIN NAMESPACE SECONDS NAME=RAD...
 *     publishes a one-point JointTrajectory (reach the positions in 1 s) on joint_trajectory
 *     every 0.1 s for SECONDS; prints `published N matched=M` (M: the most subscriptions the
 *     writer was matched with), or `refused: ...` when Cyclone does not create the writer.
 */
#include <dds/dds.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ros2_msgs.h"

#define MAX_JOINTS 64

static void topic_name(char *out, size_t n, const char *ns, const char *base)
{
    /* ROS 2 topics are DDS topics prefixed `rt/`; `/` is the root namespace. */
    if (strcmp(ns, "/") == 0)
        snprintf(out, n, "rt/%s", base);
    else
        snprintf(out, n, "rt%s/%s", ns, base);
}

static dds_entity_t participant_or_exit(long domain)
{
    dds_entity_t p = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
    if (p < 0) {
        printf("FAILED: create participant in domain %ld: %s\n", domain, dds_strretcode(p));
        exit(1);
    }
    return p;
}

static int read_states(long domain, const char *ns, long count, double timeout_s)
{
    dds_entity_t p = participant_or_exit(domain);
    char name[256];
    topic_name(name, sizeof name, ns, "joint_states");
    dds_entity_t topic =
        dds_create_topic(p, &sensor_msgs_msg_dds__JointState__desc, name, NULL, NULL);
    if (topic < 0) {
        printf("FAILED: create topic %s: %s\n", name, dds_strretcode(topic));
        return 1;
    }
    dds_qos_t *qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 100);
    dds_entity_t reader = dds_create_reader(p, topic, qos, NULL);
    dds_delete_qos(qos);
    if (reader < 0) {
        printf("refused: create reader %s: %s\n", name, dds_strretcode(reader));
        dds_delete(p);
        return 1;
    }
    /* Taken into samples of our own (no loans): the newest valid one is kept in `last`. */
    sensor_msgs_msg_dds__JointState_ *cur = sensor_msgs_msg_dds__JointState___alloc();
    sensor_msgs_msg_dds__JointState_ *last = sensor_msgs_msg_dds__JointState___alloc();
    void *samples[1];
    dds_sample_info_t info[1];
    long got = 0;
    dds_time_t end = dds_time() + (dds_duration_t)(timeout_s * 1e9);
    while (got < count && dds_time() < end) {
        samples[0] = cur;
        int n = dds_take(reader, samples, info, 1, 1);
        if (n > 0 && info[0].valid_data) {
            got++;
            sensor_msgs_msg_dds__JointState_ *t = last;
            last = cur;
            cur = t;
        } else if (n <= 0) {
            dds_sleepfor(DDS_MSECS(10));
        }
    }
    if (got < count) {
        printf("FAILED: %ld of %ld joint states on %s within %.1f s\n", got, count, name,
               timeout_s);
        fflush(stdout);
        dds_sample_free(cur, &sensor_msgs_msg_dds__JointState__desc, DDS_FREE_ALL);
        dds_sample_free(last, &sensor_msgs_msg_dds__JointState__desc, DDS_FREE_ALL);
        dds_delete(p);
        return 1;
    }
    printf("ok joint_states messages=%ld\nat:", got);
    for (uint32_t i = 0; i < last->name._length && i < last->position._length; i++)
        printf(" %s=%.4f", last->name._buffer[i], last->position._buffer[i] * 180.0 / M_PI);
    printf(" deg\n");
    fflush(stdout);
    dds_sample_free(cur, &sensor_msgs_msg_dds__JointState__desc, DDS_FREE_ALL);
    dds_sample_free(last, &sensor_msgs_msg_dds__JointState__desc, DDS_FREE_ALL);
    dds_delete(p);
    return 0;
}

static int publish_trajectory(long domain, const char *ns, double seconds, int n,
                              char **pairs)
{
    static char *names[MAX_JOINTS];
    static double positions[MAX_JOINTS], zeros[MAX_JOINTS];
    if (n < 1 || n > MAX_JOINTS) {
        printf("FAILED: give 1 to %d NAME=RAD pairs, not %d\n", MAX_JOINTS, n);
        return 2;
    }
    for (int i = 0; i < n; i++) {
        char *eq = strchr(pairs[i], '=');
        char *end = NULL;
        if (eq) positions[i] = strtod(eq + 1, &end);
        if (!eq || end == eq + 1 || *end != '\0' || !isfinite(positions[i])) {
            printf("FAILED: %s is not NAME=RAD\n", pairs[i]);
            return 2;
        }
        *eq = '\0';
        names[i] = pairs[i];
    }
    dds_entity_t p = participant_or_exit(domain);
    char name[256];
    topic_name(name, sizeof name, ns, "joint_trajectory");
    dds_entity_t topic =
        dds_create_topic(p, &trajectory_msgs_msg_dds__JointTrajectory__desc, name, NULL, NULL);
    if (topic < 0) {
        printf("refused: create topic %s: %s\n", name, dds_strretcode(topic));
        fflush(stdout);
        dds_delete(p);
        return 0;
    }
    dds_qos_t *qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
    dds_entity_t writer = dds_create_writer(p, topic, qos, NULL);
    dds_delete_qos(qos);
    if (writer < 0) {
        printf("refused: create writer %s: %s\n", name, dds_strretcode(writer));
        fflush(stdout);
        dds_delete(p);
        return 0;
    }
    trajectory_msgs_msg_dds__JointTrajectoryPoint_ point = {
        .positions = {n, (uint32_t)n, positions, false},
        .velocities = {n, (uint32_t)n, zeros, false},
        .accelerations = {0, 0, NULL, false},
        .effort = {0, 0, NULL, false},
        .time_from_start = {1, 0},
    };
    trajectory_msgs_msg_dds__JointTrajectory_ msg = {
        .header = {.stamp = {0, 0}, .frame_id = ""},
        .joint_names = {n, (uint32_t)n, names, false},
        .points = {1, 1, &point, false},
    };
    long published = 0;
    uint32_t matched = 0;
    dds_time_t end = dds_time() + (dds_duration_t)(seconds * 1e9);
    while (dds_time() < end) {
        dds_publication_matched_status_t st;
        if (dds_get_publication_matched_status(writer, &st) == DDS_RETCODE_OK &&
            st.current_count > matched)
            matched = st.current_count;
        dds_return_t rc = dds_write(writer, &msg);
        if (rc == DDS_RETCODE_OK) published++;
        dds_sleepfor(DDS_MSECS(100));
    }
    printf("published %ld matched=%u\n", published, matched);
    fflush(stdout);
    dds_delete(p);
    return 0;
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc >= 6 && strcmp(argv[1], "read") == 0)
        return read_states(strtol(argv[2], NULL, 10), argv[3], strtol(argv[4], NULL, 10),
                           strtod(argv[5], NULL));
    if (argc >= 6 && strcmp(argv[1], "trajectory") == 0)
        return publish_trajectory(strtol(argv[2], NULL, 10), argv[3], strtod(argv[4], NULL),
                                  argc - 5, argv + 5);
    fprintf(stderr,
            "usage: secure_peer read DOMAIN NAMESPACE COUNT TIMEOUT_S\n"
            "       secure_peer trajectory DOMAIN NAMESPACE SECONDS NAME=RAD...\n");
    return 2;
}
