; Tidy up: wash the mug and the saucer, the saucer first.
(define (problem tidy-up)
  (:domain kitchen)
  (:objects mug - cup
            saucer - plate)
  (:init (on-counter mug) (on-counter saucer) (hand-empty))
  (:goal (and (clean mug) (clean saucer) (on-counter mug) (on-counter saucer)))
  (:constraints (sometime-before (clean mug) (clean saucer))))
