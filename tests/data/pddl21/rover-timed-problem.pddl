; The crater road opens at time 3 (a timed initial literal).
(define (problem rover-timed-1)
  (:domain rover-temporal)
  (:objects curiosity - rover base hill crater - waypoint)
  (:init (at curiosity base) (free curiosity) (road base hill) (at 3 (road base crater)))
  (:goal (sampled crater))
  (:metric minimize (total-time)))
