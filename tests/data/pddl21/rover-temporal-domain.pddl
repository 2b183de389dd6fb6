; The rover with durations: driving takes as long as the way is long, sampling 2 time units.
(define (domain rover-temporal)
  (:requirements :strips :typing :durative-actions :timed-initial-literals)
  (:types rover waypoint)
  (:predicates (at ?r - rover ?w - waypoint)
               (road ?a ?b - waypoint)
               (free ?r - rover)
               (sampled ?w - waypoint))
  (:durative-action drive
    :parameters (?r - rover ?from ?to - waypoint)
    :duration (= ?duration 4)
    :condition (and (at start (at ?r ?from)) (over all (road ?from ?to)) (at start (free ?r)))
    :effect (and (at start (not (at ?r ?from))) (at start (not (free ?r)))
                 (at end (at ?r ?to)) (at end (free ?r))))
  (:durative-action sample
    :parameters (?r - rover ?w - waypoint)
    :duration (= ?duration 2)
    :condition (and (over all (at ?r ?w)) (at start (free ?r)))
    :effect (and (at start (not (free ?r))) (at end (free ?r)) (at end (sampled ?w)))))
